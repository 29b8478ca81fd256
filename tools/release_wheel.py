"""The `vibroimpact` wheel that needs no compiler: pure Python (py3-none-any) with the release FMUs
inside, at the places `pip install .` puts them (vibroimpact.fmu_path() finds them there).

    python tools/release_wheel.py <out folder> <package path>=<FMU>...
        e.g. dist vibroimpact/VibroImpact.fmu=dist/fmi2/VibroImpact.fmu
                  vibroimpact/fmi3/VibroImpact.fmu=dist/fmi3/VibroImpact.fmu

The Python package comes from pyproject.toml's own build (scikit-build-core, `pip wheel` with
wheel.cmake=false: no CMake, no compiler); the FMUs are added to it and to its RECORD (sha256 and
size of each file, PEP 376/427). Prints the wheel's path. Run by tools/release.sh.
"""
import base64
import hashlib
import pathlib
import subprocess
import sys
import tempfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
TIMEOUT = 600  # s, pip wheel
TAG = "py3-none-any"
FIXED_TIME = (1980, 1, 1, 0, 0, 0)  # the added files' time stamp (zip's earliest), not the build's


def fail(message):
    sys.exit(f"release_wheel: {message}")


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def base_wheel(into):
    """pyproject.toml's wheel without the CMake build: the Python package alone."""
    command = [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
               "--disable-pip-version-check", "--config-settings", "wheel.cmake=false", "-w", str(into), str(ROOT)]
    # (--config-settings, not -C: Debian 12's pip 23.0 knows only the long form)
    done = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT)
    if done.returncode != 0:
        fail(f"pip wheel failed:\n{done.stdout}{done.stderr}")
    wheels = list(into.glob("*.whl"))
    if len(wheels) != 1 or not wheels[0].name.endswith(f"-{TAG}.whl"):
        fail(f"pip wheel made {[w.name for w in wheels]}, not one {TAG} wheel")
    return wheels[0]


def add_files(wheel, out, files):
    """A copy of wheel in out/ with files ({path in the wheel: bytes}) added to it and to its RECORD."""
    dest = out / wheel.name
    with zipfile.ZipFile(wheel) as src, zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as dst:
        names = src.namelist()
        record = [n for n in names if n.endswith(".dist-info/RECORD")]
        if len(record) != 1:
            fail(f"{wheel.name} has {len(record)} RECORD files")
        binaries = [n for n in names if n.endswith((".fmu", ".so", ".dll", ".dylib"))]
        if binaries:
            fail(f"the Python package already holds {binaries}: remove them from python/vibroimpact")
        lines = [line for line in src.read(record[0]).decode().splitlines() if line and line != f"{record[0]},,"]
        for name in names:
            if name != record[0]:
                dst.writestr(src.getinfo(name), src.read(name))
        for name, data in sorted(files.items()):
            info = zipfile.ZipInfo(name, FIXED_TIME)
            info.external_attr = 0o644 << 16
            dst.writestr(info, data, zipfile.ZIP_DEFLATED)
            lines.append(record_line(name, data))
        lines.append(f"{record[0]},,")
        dst.writestr(src.getinfo(record[0]), "\n".join(lines) + "\n")
    return dest


def main():
    if len(sys.argv) < 3:
        fail("usage: release_wheel.py <out folder> <package path>=<FMU>...")
    out = pathlib.Path(sys.argv[1])
    files = {}
    for arg in sys.argv[2:]:
        name, _, path = arg.partition("=")
        if not name.startswith("vibroimpact/") or not pathlib.Path(path).is_file():
            fail(f"{arg}: give vibroimpact/<path in the package>=<an existing FMU>")
        files[name] = pathlib.Path(path).read_bytes()
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob(f"vibroimpact-*-{TAG}.whl"):
        old.unlink()
    with tempfile.TemporaryDirectory() as tmp:
        print(add_files(base_wheel(pathlib.Path(tmp)), out, files))


if __name__ == "__main__":
    main()
