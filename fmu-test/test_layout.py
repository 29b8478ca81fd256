"""The tree of src/ is the architecture doc/layout.md describes: one folder per layer, each layer's
files including only headers of its own folder and of the layers below it, every file of src/ named
on the page. The rule is read from the includes themselves, so a header moved or an include added
across layers fails here."""
import re

import pytest

from conftest import ROOT

SRC = ROOT / "src"
# Each layer and the layers whose headers it may include (its own folder always).
BELOW = {
    "base": set(),
    "profile": {"base"},
    "model": {"base", "profile"},
    "solvers": {"base"},
    "engine": {"base", "profile", "model", "solvers"},
    "drivers": {"base", "profile", "model", "solvers", "engine"},
    "fmi": {"base"},
    "adapter": {"base", "profile", "model", "solvers", "engine", "drivers", "fmi"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def layer_of_header():
    """{header name: its layer} for every header and table of src/."""
    where = {}
    for p in SRC.rglob("*"):
        if p.suffix in {".h", ".inc"}:
            assert p.name not in where, f"{p.name} is in two layers: {where[p.name]} and {p.parent.name}"
            where[p.name] = p.parent.name
    return where


def test_every_file_of_src_is_in_a_layer_folder():
    loose = [p.relative_to(ROOT).as_posix() for p in SRC.iterdir() if p.is_file()]
    folders = {p.name for p in SRC.iterdir() if p.is_dir()}
    assert not loose, f"files of src/ outside a layer's folder: {loose}"
    assert folders == set(BELOW), f"the layers' folders {sorted(folders)} are not the rule's {sorted(BELOW)}"


@pytest.mark.parametrize("layer", sorted(BELOW))
def test_a_layer_includes_only_its_own_headers_and_those_below_it(layer):
    where = layer_of_header()
    allowed = BELOW[layer] | {layer}
    crossings = []
    for p in sorted((SRC / layer).iterdir()):
        for name in INCLUDE.findall(p.read_text()):
            if name in where and where[name] not in allowed:
                crossings.append(f"{p.relative_to(ROOT)} includes {name} of src/{where[name]}/")
    checked = sum(len(INCLUDE.findall(p.read_text())) for p in (SRC / layer).iterdir())
    assert checked > 0, f"src/{layer}/ includes nothing: the rule checks nothing"
    assert not crossings, f"src/{layer}/ may include only src/{{{', '.join(sorted(allowed))}}}:\n" + "\n".join(crossings)


def test_the_rule_sees_a_crossing():
    """The engine's header including a driver's would be a crossing: the rule must see it."""
    where = layer_of_header()
    assert where["vi_run.h"] == "drivers" and "drivers" not in BELOW["engine"]
    assert where["vi_model.h"] == "model" and "model" not in BELOW["fmi"]


def test_layout_md_names_every_layer_and_file():
    """Every folder and file, a C file also through its header of the same name (vi_x.c implements vi_x.h)."""
    page = (ROOT / "doc" / "layout.md").read_text()
    listing = page[page.index("```"):]
    missing = []
    for p in sorted(SRC.rglob("*")):
        if p.is_dir():
            if f"src/{p.name}/" not in listing:
                missing.append(f"src/{p.name}/")
        elif p.name not in listing and f"{p.stem}.h" not in listing and not any(
                re.fullmatch(g.replace("*", ".*"), p.name) for g in re.findall(r"vi_\w*\*\.c", listing)):
            missing.append(p.relative_to(ROOT).as_posix())
    assert not missing, "doc/layout.md does not name: " + ", ".join(missing)
