"""The shape of the Python package: a library that reads no command-line options and does nothing when
imported, and one command layer, vibroimpact.cli, with a module per command.

Every library module (all of vibroimpact but vibroimpact.cli and __main__) is imported in a fresh
interpreter started in an empty folder: none of them imports argparse (fmpy and SciPy import it for
themselves, so the import statements of the package's own modules are what is watched), matplotlib
is not imported at all (the figures import it when they are made), nothing is printed and no file is
written, neither in the working folder nor in the package. The sources are read too: no module outside
vibroimpact.cli imports argparse anywhere, not even inside a function.
"""
import ast
import pathlib
import subprocess
import sys
import tomllib

import vibroimpact
from conftest import ROOT

PACKAGE = pathlib.Path(vibroimpact.__file__).resolve().parent
IMPORT_TIMEOUT_S = 120
COMMAND_LAYER = ("cli", "__main__")   # the parts of the package that read options

# Run in a fresh interpreter: records every import statement executed by a module of the package
# (builtins.__import__ sees it even when the module is already loaded), then imports every library module.
PROBE = r"""
import builtins, importlib, json, pathlib, sys
seen = []
real_import = builtins.__import__
def watch(name, globals=None, locals=None, fromlist=(), level=0):
    importer = (globals or {}).get("__name__", "")
    if importer.startswith("vibroimpact"):
        seen.append((importer, name, list(fromlist or ())))
    return real_import(name, globals, locals, fromlist, level)
builtins.__import__ = watch
import vibroimpact
top = pathlib.Path(vibroimpact.__file__).parent
# from the files (pkgutil.walk_packages would import the command layer's package to look inside)
names = sorted(".".join(("vibroimpact",) + p.relative_to(top).with_suffix("").parts).removesuffix(".__init__")
               for p in top.rglob("*.py") if p.relative_to(top).parts[0].removesuffix(".py") not in sys.argv[1:])
for name in names:
    importlib.import_module(name)
builtins.__import__ = real_import
print(json.dumps(dict(modules=names, seen=seen, loaded=sorted(sys.modules))))
"""


def files_under(folder):
    """Every file under folder (bytecode caches left out) with its size and modification time."""
    return {p: (p.stat().st_size, p.stat().st_mtime_ns) for p in folder.rglob("*")
            if p.is_file() and "__pycache__" not in p.parts}


def test_importing_the_library_reads_no_options_draws_nothing_and_writes_nothing(tmp_path):
    import json
    before = files_under(PACKAGE)
    p = subprocess.run([sys.executable, "-B", "-c", PROBE, *COMMAND_LAYER], cwd=tmp_path, capture_output=True, text=True,
                       timeout=IMPORT_TIMEOUT_S)
    assert p.returncode == 0, p.stderr[-3000:]
    report = json.loads(p.stdout.strip().splitlines()[-1])
    assert p.stdout.strip().count("\n") == 0, f"importing the library printed: {p.stdout[:2000]}"
    assert len(report["modules"]) >= 20, report["modules"]   # the walk found the package
    for must in ("vibroimpact.fmu", "vibroimpact.fmi3", "vibroimpact.plotting", "vibroimpact.bench",
                 "vibroimpact.sweep.engine", "vibroimpact.reference.model"):
        assert must in report["modules"], must
    argparse_users = sorted({who for who, name, _ in report["seen"] if name == "argparse"})
    assert not argparse_users, f"library modules importing argparse: {argparse_users}"
    assert not [m for m in report["loaded"] if m == "matplotlib" or m.startswith("matplotlib.")], \
        "importing the library imported matplotlib"
    assert list(tmp_path.iterdir()) == [], f"written in the working folder: {list(tmp_path.iterdir())}"
    assert files_under(PACKAGE) == before, "importing the library changed files in the package"


def imports_of(path):
    """The top-level names of every module an import statement anywhere in the file names."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return found


def test_no_library_module_imports_argparse_anywhere():
    library = [p for p in PACKAGE.rglob("*.py") if p.relative_to(PACKAGE).parts[0].removesuffix(".py")
               not in COMMAND_LAYER]
    assert len(library) >= 20, library
    users = [str(p.relative_to(PACKAGE)) for p in library if "argparse" in imports_of(p)]
    assert not users, f"argparse imported outside vibroimpact.cli: {users}"
    assert any("argparse" in imports_of(p) for p in (PACKAGE / "cli").glob("*.py"))   # the check sees imports


def test_every_command_is_a_module_of_the_command_layer_and_the_entry_point_is_its_dispatcher():
    from vibroimpact import cli
    modules = {p.stem for p in (PACKAGE / "cli").glob("*.py")} - {"__init__"}
    named = {module for module, _ in cli.COMMANDS.values()}
    assert named == modules, (sorted(named ^ modules))
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts == {"vibroimpact": "vibroimpact.cli:main"}


def test_no_command_writes_into_doc_or_the_package_unless_told():
    """Every command's default output folder is under results/ of the working folder (the gallery
    copies of the figures go only where --gallery DIR names, and bench and reference write into doc/
    and the package's data only when --out names them)."""
    import importlib

    from vibroimpact import cli
    from vibroimpact.cli import sweep
    defaults = {name: importlib.import_module(f"vibroimpact.cli.{module}").OUT
                for name, (module, _) in cli.COMMANDS.items()
                if hasattr(importlib.import_module(f"vibroimpact.cli.{module}"), "OUT")}
    defaults["sweep"] = pathlib.Path(sweep.parse_args([]).out)
    assert {"paper", "rolling", "sweep", "diagrams", "bench", "reference"} <= set(defaults), defaults
    for name, out in defaults.items():
        assert not out.is_absolute() and out.parts[0] == "results", (name, out)
