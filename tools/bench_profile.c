/* bench_profile - the cost of loading a rolling profile (vi_profile_load: reading the file and building
 * the rigid-constraint envelope), for tools/bench.py.
 *
 *   vi_bench_profile FILE R1 PERIODIC REPEATS [INTERPOLATION]
 *
 * Loads FILE REPEATS times with radius R1 [m] (PERIODIC 0 or 1), the rows joined as INTERPOLATION says
 * (1 linear, the default; 2 the cubic spline: vi_profile.h), and prints
 *   cpu_s <min CPU seconds of one load> kinks <kinks of the rigid constraint>
 *   maxrss_kb <peak resident memory of this process [kB]: VmHWM of /proc/self/status, which starts
 *              afresh at exec (getrusage's maxrss where there is none; Linux carries that one over
 *              from the parent at fork, so a large parent hides the loading)>
 * The minimum is taken because the machine may be shared. Exit status 1 when the file is refused
 * (the message is printed). */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

#include "vi_profile.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc != 5 && argc != 6) {
        fprintf(stderr, "usage: %s FILE R1 PERIODIC REPEATS [INTERPOLATION]\n", argv[0]);
        return 2;
    }
    double R = atof(argv[2]), best = 1e300;
    int periodic = atoi(argv[3]), repeats = atoi(argv[4]), interpolation = argc == 6 ? atoi(argv[5]) : VI_PROFILE_LINEAR;
    size_t kinks = 0;
    char msg[8192];
    for (int k = 0; k < repeats; k++) {
        double c0 = cpu_now();
        vi_profile *p = vi_profile_load_as(argv[1], R, periodic, interpolation, msg, sizeof msg);
        double c1 = cpu_now();
        if (!p) {
            fprintf(stderr, "%s\n", msg);
            return 1;
        }
        kinks = vi_profile_kinks(p);
        vi_profile_free(p);
        if (c1 - c0 < best) best = c1 - c0;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    long peak_kb = (long)ru.ru_maxrss;
    FILE *status = fopen("/proc/self/status", "r");
    char line[256];
    while (status && fgets(line, sizeof line, status)) /* bounded by the file */
        if (sscanf(line, "VmHWM: %ld kB", &peak_kb) == 1) break;
    if (status) fclose(status);
    printf("cpu_s %.9g kinks %zu maxrss_kb %ld\n", best, kinks, peak_kb);
    return 0;
}
