"""Build the binary of a source FMU from its sources/ alone, as an importer does: the FMU is unpacked,
its binaries/ deleted, and the C files and preprocessor definitions its model description (FMI 2.0
<SourceFiles>) or sources/buildDescription.xml (FMI 3.0) lists, read by fmpy, are compiled with the
sources/ folder and the FMI headers as the only include paths.

    python tools/fmu_source_build.py fmpy <fmu> <out folder>
        fmpy's own source build (fmpy.build.build_platform_binary: its CMake project, this machine's
        compiler)
    python tools/fmu_source_build.py cc <fmu> <out folder> --target <platform> -- <compiler command...>
        one command of a GCC-like compiler: x86_64-windows (x86_64-w64-mingw32-gcc), x86_64-darwin
        and aarch64-darwin (`python -m ziglang cc -target x86_64-macos`, `... aarch64-macos`),
        x86_64-linux, aarch64-linux; the library exports the FMI functions only (hidden visibility,
        and on Windows only what is dllexport), links the C library alone (Windows: libgcc statically)

The out folder gets modelDescription.xml (the FMU's) and binaries/<folder>/<model identifier>.<ext>,
the folder being FMI 2.0's name of the platform (linux64, win64, darwin64) or FMI 3.0's tuple.
Exits non-zero, with the compiler's messages, when the build fails.
"""
import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile
import zipfile

TIMEOUT = 1200  # s, one build
EXTENSION = {"windows": ".dll", "darwin": ".dylib", "linux": ".so"}
FMI2_PLATFORM = {"x86_64-windows": "win64", "x86_64-darwin": "darwin64", "x86_64-linux": "linux64"}
# Release flags as CMake's (-O3 -DNDEBUG), C11 as the sources declare, and per system what keeps the
# binary to the FMI functions and the system's C library.
COMMON_FLAGS = ["-shared", "-O3", "-DNDEBUG", "-std=c11", "-s"]  # -s: stripped, as the release binaries
SYSTEM_FLAGS = {
    "windows": ["-static-libgcc", "-Wl,--no-insert-timestamp"],
    "darwin": ["-fPIC", "-fvisibility=hidden"],
    "linux": ["-fPIC", "-fvisibility=hidden", "-Wl,--no-undefined", "-lm"],
}


def fail(message):
    sys.exit(f"fmu_source_build: {message}")


def unpack(fmu, into):
    """The FMU unpacked into `into` without its binaries/; its model description read by fmpy."""
    from fmpy import read_model_description
    with zipfile.ZipFile(fmu) as z:
        z.extractall(into)
    shutil.rmtree(into / "binaries", ignore_errors=True)
    md = read_model_description(str(into))
    if not md.buildConfigurations or not md.buildConfigurations[0].sourceFileSets:
        fail(f"{fmu} lists no source files: not a source FMU")
    return md


def identifier(md):
    return (md.coSimulation or md.modelExchange).modelIdentifier


def platform_folder(md, target):
    if md.fmiVersion.startswith("2"):
        if target not in FMI2_PLATFORM:
            fail(f"FMI 2.0 names no platform for {target}")
        return FMI2_PLATFORM[target]
    return target


def fmi_headers():
    import fmpy
    return pathlib.Path(fmpy.__file__).parent / "c-code"


def build_cc(unzipdir, md, target, compiler):
    """The binary compiled in one command; returns its path."""
    system = target.split("-", 1)[1]
    if system not in SYSTEM_FLAGS:
        fail(f"unknown platform {target} (arch-system: windows, darwin, linux)")
    file_set = md.buildConfigurations[0].sourceFileSets[0]
    sources = unzipdir / "sources"
    out = unzipdir / "binaries" / platform_folder(md, target) / (identifier(md) + EXTENSION[system])
    out.parent.mkdir(parents=True)
    defines = [f"-D{d.name}={d.value}" if d.value else f"-D{d.name}" for d in file_set.preprocessorDefinitions]
    name_flags = [f"-Wl,-install_name,@rpath/{out.name}"] if system == "darwin" else []  # not the build's path
    command = (list(compiler) + COMMON_FLAGS + [f"-I{sources}", f"-I{fmi_headers()}"] + defines
               + [str(sources / f) for f in file_set.sourceFiles] + ["-o", str(out)] + SYSTEM_FLAGS[system]
               + name_flags)
    run(command, unzipdir)
    return out


def build_fmpy(unzipdir, md):
    """fmpy's own source build for this machine; returns the binary's path."""
    import fmpy
    from fmpy.build import build_platform_binary
    folder = fmpy.platform if md.fmiVersion.startswith("2") else fmpy.platform_tuple
    with tempfile.TemporaryDirectory() as build:
        try:
            build_platform_binary(str(unzipdir), build_dir=build)
        except subprocess.CalledProcessError as e:
            fail(f"fmpy's source build failed ({' '.join(e.cmd[:3])} ...: its messages above)")
    found = list((unzipdir / "binaries" / folder).glob(identifier(md) + ".*"))
    if len(found) != 1:
        fail(f"fmpy's build left {found} in binaries/{folder}")
    return found[0]


def run(command, cwd):
    try:
        done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT)
    except FileNotFoundError:
        fail(f"{command[0]} not found (tools/release.sh installs the compilers)")
    except subprocess.TimeoutExpired:
        fail(f"the build took more than {TIMEOUT} s: {' '.join(command[:4])} ...")
    if done.returncode != 0:
        fail(f"the build failed ({' '.join(command[:4])} ...):\n{done.stdout}{done.stderr}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("how", choices=["fmpy", "cc"])
    p.add_argument("fmu", type=pathlib.Path)
    p.add_argument("out", type=pathlib.Path, help="the folder to write modelDescription.xml and binaries/ into")
    p.add_argument("--target", help="cc: the platform (FMI 3.0 tuple)")
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    args = p.parse_args(argv[:split])
    args.compiler = argv[split + 1:]
    if args.how == "cc" and not (args.target and args.compiler):
        fail("cc needs --target and the compiler command after --")
    with tempfile.TemporaryDirectory() as tmp:
        unzipdir = pathlib.Path(tmp) / "fmu"
        md = unpack(args.fmu, unzipdir)
        binary = build_fmpy(unzipdir, md) if args.how == "fmpy" else build_cc(unzipdir, md, args.target, args.compiler)
        dest = args.out / binary.relative_to(unzipdir)
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(binary, dest)
        shutil.copyfile(unzipdir / "modelDescription.xml", args.out / "modelDescription.xml")
        print(dest)


if __name__ == "__main__":
    main()
