/*
 * vi_format.h - VI_PRINTF_FORMAT(f, a): the compiler checks the printf-style format at argument f
 * against the arguments from a. The build uses the C99 printf everywhere, also on Windows, where
 * MinGW-w64's own stdio is linked in (cmake/vi_platform.cmake): its checker is gnu_printf there
 * (plain `printf` would mean the C runtime's, which knows no %zu).
 */
#ifndef VI_FORMAT_H
#define VI_FORMAT_H

#if defined(__MINGW32__)
#define VI_PRINTF_FORMAT(f, a) __attribute__((format(gnu_printf, f, a)))
#elif defined(__GNUC__) || defined(__clang__)
#define VI_PRINTF_FORMAT(f, a) __attribute__((format(printf, f, a)))
#else
#define VI_PRINTF_FORMAT(f, a) /* a compiler without the GNU attribute (MSVC) checks nothing */
#endif

#endif
