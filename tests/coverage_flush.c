/*
 * coverage_flush.c - in coverage builds only (tests/coverage.cmake, for tools/mutate.py): one
 * exported function that writes the gcov counters of the binary it is linked into and resets them,
 * so that a test runner can attribute the lines each test executes to that test while the FMU stays
 * loaded in its process.
 */
extern void __gcov_dump(void);
extern void __gcov_reset(void);

__attribute__((visibility("default"))) void vi_coverage_flush(void)
{
    __gcov_dump();
    __gcov_reset();
}
