"""Write the sources/ folder of a source FMU: everything an importer needs to compile the FMU's
binary for any platform, with no SUNDIALS installed.

Run at build time by vi_add_fmu() (cmake/vi_fmu.cmake) when VI_FMU_SUNDIALS_SOURCES names SUNDIALS'
source tree (tools/release.sh):

    python vi_fmu_sources.py --out STAGE/sources --sundials SUNDIALS_SOURCE_TREE
        --sources C_FILES... --include-dirs DIRS... --fmi-headers FMI_HEADER_DIR
        [--fmi2-xml modelDescription.xml --fmi2-xml-out OUT.xml]
        [--build-description MODEL_IDENTIFIER --define NAME=VALUE...]

What goes in (one flat folder, so that the folder itself is the only include path, which is all FMI
2.0 and fmpy's source build give):
  - the model's C files and every header they include (found as the compiler finds them: the
    including file's folder, then the include dirs); the FMI headers are the importer's, not copied
  - when a file includes a SUNDIALS header, the SUNDIALS C files the FMUs link (SUNDIALS_SOURCES)
    with every header they include, at the place their #include lines name them: include/<pkg>/x.h
    and src/<pkg>/.../x.c in <pkg>/, SUNDIALS' private headers (src/sundials/*.h, which the packages
    include by name) at the top; sundials_config.h and sundials_export.h, which SUNDIALS' CMake
    generates, are written here (CONFIG_H, EXPORT_H) for any platform and compiler; and SUNDIALS'
    LICENSE and NOTICE, as SUNDIALS-LICENSE and SUNDIALS-NOTICE
Every #include of every copied file is resolved again inside the folder, from the file's own folder
and the top only: one that finds another file than the original build did (or none) fails the run.

FMI 2.0: --fmi2-xml-out is the model description with <SourceFiles> listing the C files in
<ModelExchange> and <CoSimulation>. FMI 3.0: --build-description writes sources/buildDescription.xml
(one BuildConfiguration, language C11, the --define preprocessor definitions).
"""
import argparse
import pathlib
import re
import shutil
import sys
from xml.sax.saxutils import quoteattr

# The C files of SUNDIALS 6.4.1's CVODE library that the FMUs use: the members of libsundials_cvode.a
# that the linker takes for src/solvers/vi_solver.c (ld -Map). A missing one fails the links of the source
# builds (tools/fmu_source_build.py: undefined symbols).
SUNDIALS_SOURCES = [
    "src/cvode/cvode.c", "src/cvode/cvode_io.c", "src/cvode/cvode_ls.c", "src/cvode/cvode_nls.c",
    "src/cvode/cvode_proj.c",
    "src/nvector/serial/nvector_serial.c",
    "src/sundials/sundials_context.c", "src/sundials/sundials_dense.c", "src/sundials/sundials_linearsolver.c",
    "src/sundials/sundials_logger.c", "src/sundials/sundials_math.c", "src/sundials/sundials_matrix.c",
    "src/sundials/sundials_nonlinearsolver.c", "src/sundials/sundials_nvector.c",
    "src/sundials/sundials_nvector_senswrapper.c",
    "src/sunlinsol/dense/sunlinsol_dense.c",
    "src/sunmatrix/band/sunmatrix_band.c", "src/sunmatrix/dense/sunmatrix_dense.c",
    "src/sunnonlinsol/newton/sunnonlinsol_newton.c",
]
SUNDIALS_VERSION = (6, 4, 1)
SUNDIALS_LICENCE_FILES = {"LICENSE": "SUNDIALS-LICENSE", "NOTICE": "SUNDIALS-NOTICE"}

# sundials_config.h as SUNDIALS' CMake writes it for a CVODE-only build in double precision with
# 64-bit indices, no MPI, no profiling, logging level 0 (what tools/release.sh builds for the cross
# platforms), made independent of the platform and the compiler: it relies on C99 only.
CONFIG_H = """\
/* sundials_config.h for the source FMU: the configuration of SUNDIALS {v} that tools/release.sh
 * builds (CVODE, double precision, 64-bit indices, no MPI, no profiling, logging level 0), for any
 * C99 compiler. Written by cmake/vi_fmu_sources.py in place of the header SUNDIALS' CMake generates. */
#ifndef _SUNDIALS_CONFIG_H
#define _SUNDIALS_CONFIG_H

#include "sundials/sundials_export.h"

#ifndef SUNDIALS_DEPRECATED_MSG
#define SUNDIALS_DEPRECATED_MSG(msg)
#endif
#ifndef SUNDIALS_DEPRECATED_EXPORT_MSG
#define SUNDIALS_DEPRECATED_EXPORT_MSG(msg) SUNDIALS_EXPORT SUNDIALS_DEPRECATED_MSG(msg)
#endif
#ifndef SUNDIALS_DEPRECATED_NO_EXPORT_MSG
#define SUNDIALS_DEPRECATED_NO_EXPORT_MSG(msg) SUNDIALS_NO_EXPORT SUNDIALS_DEPRECATED_MSG(msg)
#endif

#define SUNDIALS_VERSION "{v}"
#define SUNDIALS_VERSION_MAJOR {major}
#define SUNDIALS_VERSION_MINOR {minor}
#define SUNDIALS_VERSION_PATCH {patch}
#define SUNDIALS_VERSION_LABEL ""
#define SUNDIALS_GIT_VERSION ""

#define SUNDIALS_C_COMPILER_HAS_MATH_PRECISIONS
#define SUNDIALS_C_COMPILER_HAS_ISINF_ISNAN
#define SUNDIALS_C_COMPILER_HAS_INLINE
#define SUNDIALS_C_COMPILER_HAS_SNPRINTF_AND_VA_COPY

#define SUNDIALS_DOUBLE_PRECISION 1
#define SUNDIALS_INT64_T 1
#define SUNDIALS_INDEX_TYPE int64_t

#define SUNDIALS_LOGGING_LEVEL 0
#define SUNDIALS_MPI_ENABLED 0

#define SUNDIALS_CVODE 1
#define SUNDIALS_NVECTOR_SERIAL 1
#define SUNDIALS_SUNMATRIX_BAND 1
#define SUNDIALS_SUNMATRIX_DENSE 1
#define SUNDIALS_SUNLINSOL_DENSE 1
#define SUNDIALS_SUNNONLINSOL_NEWTON 1

#ifndef SUNDIALS_C_INLINE
#define SUNDIALS_C_INLINE inline
#endif
#ifndef SUNDIALS_CXX_INLINE
#define SUNDIALS_CXX_INLINE inline
#endif
#ifdef __cplusplus
#define SUNDIALS_INLINE SUNDIALS_CXX_INLINE
#else
#define SUNDIALS_INLINE SUNDIALS_C_INLINE
#endif
#define SUNDIALS_STATIC_INLINE static SUNDIALS_INLINE

#endif /* _SUNDIALS_CONFIG_H */
"""

# sundials_export.h: SUNDIALS is compiled into the FMU's binary, never exported from it (hidden
# where the compiler has visibility; on Windows a DLL exports only what is marked dllexport).
EXPORT_H = """\
/* sundials_export.h for the source FMU: SUNDIALS is linked into the FMU's binary and exports
 * nothing from it. Written by cmake/vi_fmu_sources.py in place of the header SUNDIALS' CMake
 * generates. */
#ifndef SUNDIALS_EXPORT_H
#define SUNDIALS_EXPORT_H

#if (defined(__GNUC__) || defined(__clang__)) && !defined(_WIN32) && !defined(__CYGWIN__)
#define SUNDIALS_EXPORT __attribute__((visibility("hidden")))
#else
#define SUNDIALS_EXPORT
#endif
#define SUNDIALS_NO_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED
#define SUNDIALS_DEPRECATED_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED_NO_EXPORT SUNDIALS_NO_EXPORT

#endif /* SUNDIALS_EXPORT_H */
"""
GENERATED = {"sundials/sundials_config.h": None, "sundials/sundials_export.h": EXPORT_H}

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
MAX_FILES = 1000  # bounds the walk through the includes


def fail(message):
    sys.exit(f"vi_fmu_sources: {message}")


def includes(path):
    """(quoted, name) of every #include line of a file, in order."""
    text = path.read_text(encoding="utf-8", errors="replace")
    return [(kind == '"', name) for kind, name in INCLUDE.findall(text)]


class Layout:
    """Where each original file goes in sources/ (a name relative to it), and back."""

    def __init__(self, sundials, fmi_dir):
        self.sundials = sundials
        self.fmi_dir = fmi_dir
        self.dest = {}    # original path -> name in sources/
        self.origin = {}  # name in sources/ -> original path (None: written here)
        for name in GENERATED:
            self.origin[name] = None

    def place(self, path, name):
        if self.origin.get(name, path) != path:
            fail(f"{path} and {self.origin[name]} would both be sources/{name}")
        if self.dest.get(path, name) != name:
            fail(f"{path} would be both sources/{self.dest[path]} and sources/{name}")
        self.dest[path] = name
        self.origin[name] = path

    def in_sundials(self, path):
        return self.sundials in path.parents

    def name_for(self, path):
        """The name in sources/: the model's files at the top; SUNDIALS' as described above."""
        if not self.in_sundials(path):
            return path.name
        rel = path.relative_to(self.sundials)
        if rel.parts[0] == "include":
            return "/".join(rel.parts[1:])
        if rel.parts[0] == "src" and rel.parts[1] == "sundials" and path.suffix == ".h":
            return path.name  # a private header the packages include by name
        if rel.parts[0] == "src":
            return f"{rel.parts[1]}/{path.name}"
        fail(f"{path}: no place for this SUNDIALS file")


def find(name, quoted, here, dirs):
    """The file an #include names, searched as the compiler does: the including file's folder (for
    "..."), then dirs; None when not found there (a system or importer's header)."""
    for d in ([here] if quoted else []) + list(dirs):
        candidate = (d / name).resolve()
        if candidate.is_file():
            return candidate
    return None


def walk(layout, todo, search, seen):
    """Place every file of todo and every file it includes (search(path): the folders an #include of
    path is looked up in after its own folder); returns the files found in SUNDIALS' tree."""
    found_sundials = []
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        if len(seen) >= MAX_FILES:
            fail(f"more than {MAX_FILES} files: an include loop?")
        seen[path] = search(path)
        layout.place(path, layout.name_for(path))
        for quoted, name in includes(path):
            found = None if name in GENERATED else find(name, quoted, path.parent, seen[path])
            if found is None or found.parent == layout.fmi_dir:
                continue  # a system header, an importer's (FMI) header, or one written here
            if layout.in_sundials(found):
                found_sundials.append(found)
            todo.append(found)
    return found_sundials


def collect(args):
    """The layout of every file to copy, the folders each one's includes were looked up in, the C
    files to compile (names in sources/), and whether SUNDIALS is in."""
    sundials = pathlib.Path(args.sundials).resolve()
    layout = Layout(sundials, pathlib.Path(args.fmi_headers).resolve())
    sundials_dirs = [sundials / "include", sundials / "src" / "sundials"]
    own_dirs = [pathlib.Path(d).resolve() for d in args.include_dirs] + [layout.fmi_dir] + sundials_dirs
    c_files = [pathlib.Path(f).resolve() for f in args.sources]
    seen = {}
    search = lambda path: sundials_dirs if layout.in_sundials(path) else own_dirs
    uses_sundials = bool(walk(layout, list(c_files), search, seen))
    if uses_sundials:
        extra = [sundials / f for f in SUNDIALS_SOURCES]
        for f in extra:
            if not f.is_file():
                fail(f"{f} not found: is {sundials} SUNDIALS {'.'.join(map(str, SUNDIALS_VERSION))}?")
        c_files += extra
        walk(layout, list(extra), search, seen)
    return layout, seen, [layout.dest[f] for f in c_files], uses_sundials


def check_layout(layout, seen, out):
    """Every #include of a copied file finds, inside out/ (the file's folder, then out/), the file the
    original build found: else the source FMU would not compile, or would compile something else."""
    for path, dirs in seen.items():
        here = (out / layout.dest[path]).parent
        for quoted, name in includes(path):
            if name in GENERATED:
                expected = name
            else:
                original = find(name, quoted, path.parent, dirs)
                if original is None or original.parent == layout.fmi_dir:
                    continue
                expected = layout.dest[original]
            got = find(name, quoted, here, [out])
            if got != (out / expected).resolve():
                fail(f"sources/{layout.dest[path]}: #include {name} finds {got} there, not sources/{expected}")


def write_sources(args, layout, uses_sundials):
    out = pathlib.Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    for name, origin in layout.origin.items():
        if origin is None:
            continue
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(origin, out / name)
    if uses_sundials:
        major, minor, patch = SUNDIALS_VERSION
        v = f"{major}.{minor}.{patch}"
        (out / "sundials").mkdir(parents=True, exist_ok=True)
        (out / "sundials/sundials_config.h").write_text(
            CONFIG_H.replace("{v}", v).replace("{major}", str(major)).replace("{minor}", str(minor))
            .replace("{patch}", str(patch)))
        (out / "sundials/sundials_export.h").write_text(EXPORT_H)
        for src, dst in SUNDIALS_LICENCE_FILES.items():
            shutil.copyfile(pathlib.Path(args.sundials) / src, out / dst)
    return out


def source_files_xml(c_files, indent):
    lines = [f"{indent}<SourceFiles>"]
    lines += [f"{indent}  <File name={quoteattr(f)}/>" for f in c_files]
    lines.append(f"{indent}</SourceFiles>")
    return "\n".join(lines)


def write_fmi2_xml(src, dst, c_files):
    """The FMI 2.0 model description with <SourceFiles> in <ModelExchange> and <CoSimulation>
    (their only child in the schema), the rest of the text as it is."""
    text = pathlib.Path(src).read_text(encoding="utf-8")
    if "<SourceFiles" in text:
        fail(f"{src} already lists source files")
    count = 0
    for element in ("ModelExchange", "CoSimulation"):
        opening = re.search(rf"^([ \t]*)<{element}\b[^>]*?(/?)>", text, re.M | re.S)
        if not opening:
            continue
        indent, closed = opening.group(1), opening.group(2) == "/"
        body = source_files_xml(c_files, indent + "  ")
        tag = opening.group(0)
        if closed:
            new = tag[:-2].rstrip() + ">\n" + body + f"\n{indent}</{element}>"
        else:
            new = tag + "\n" + body
        text = text[:opening.start()] + new + text[opening.end():]
        count += 1
    if count == 0:
        fail(f"{src} has neither <ModelExchange> nor <CoSimulation>")
    pathlib.Path(dst).write_text(text, encoding="utf-8")


def write_build_description(out, identifier, c_files, defines):
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             '<fmiBuildDescription fmiVersion="3.0">',
             f"  <BuildConfiguration modelIdentifier={quoteattr(identifier)}>",
             '    <SourceFileSet language="C11">']
    lines += [f"      <SourceFile name={quoteattr(f)}/>" for f in c_files]
    for d in defines:
        name, _, value = d.partition("=")
        lines.append(f"      <PreprocessorDefinition name={quoteattr(name)} value={quoteattr(value)}/>")
    lines += ["    </SourceFileSet>", "  </BuildConfiguration>", "</fmiBuildDescription>", ""]
    (out / "buildDescription.xml").write_text("\n".join(lines), encoding="utf-8")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True, help="the sources/ folder to write (emptied first)")
    p.add_argument("--sundials", required=True, help="SUNDIALS' source tree")
    p.add_argument("--sources", nargs="+", required=True, help="the model's C files")
    p.add_argument("--include-dirs", nargs="*", default=[], help="the model's include folders")
    p.add_argument("--fmi-headers", required=True, help="the folder of the FMI headers (not copied)")
    p.add_argument("--fmi2-xml", help="the FMI 2.0 model description")
    p.add_argument("--fmi2-xml-out", help="where to write it with <SourceFiles>")
    p.add_argument("--build-description", metavar="MODEL_IDENTIFIER", help="write buildDescription.xml (FMI 3.0)")
    p.add_argument("--define", nargs="*", default=[], help="NAME=VALUE preprocessor definitions (FMI 3.0)")
    args = p.parse_args()
    layout, seen, c_files, uses_sundials = collect(args)
    out = write_sources(args, layout, uses_sundials)
    check_layout(layout, seen, out.resolve())
    if args.fmi2_xml:
        write_fmi2_xml(args.fmi2_xml, args.fmi2_xml_out, c_files)
    if args.build_description:
        write_build_description(out, args.build_description, c_files, args.define)


if __name__ == "__main__":
    main()
