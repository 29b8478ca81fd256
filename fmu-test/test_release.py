"""What a user may take: every FMU of the build carries the licences (the repository's LICENSE, and
SUNDIALS' copyright file for the CVODE code its binaries hold), the documentation page FMI names as
the entry point (FMI 2.0 documentation/_main.html, FMI 3.0 documentation/index.html), whose every
link and image resolves inside the FMU, the model's icon, and the release version and generation
date in its model description; the version is the CMake project's everywhere (CITATION.cff,
CHANGELOG.md, the wheel's metadata); and the Markdown converter and the stamp give what Markdown
and xs:dateTime define."""
import datetime
import html.parser
import importlib.util
import posixpath
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import pytest
from fmpy import read_model_description

from conftest import BUILD, ROOT

SUNDIALS_COPYRIGHT = "/usr/share/doc/libsundials-dev/copyright"  # VI_SUNDIALS_LICENSE's default (CMakeLists.txt)
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
ENTRY = {2: "documentation/_main.html", 3: "documentation/index.html"}
# name -> whether its binaries link SUNDIALS CVODE (CMakeLists.txt, examples/vehicle-track/CMakeLists.txt)
MODELS = {"VibroImpact": True, "Track": True, "Vehicle": True, "LayerTest": False}
XS_DATETIME_UTC = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ")


def project_version():
    m = re.search(r"project\(VibroImpact VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    assert m, "CMakeLists.txt: no project(VibroImpact VERSION ...)"
    return m.group(1)


def fmu(name, version):
    path = BUILD / (f"{name}.fmu" if version == 2 else f"fmi3/{name}.fmu")
    if not path.exists():
        pytest.fail(f"{path} is missing: build with cmake --build build")
    return path


def load(script):
    """A build script of cmake/ as a module; the scripts beside it that it imports come first (as
    sys.modules entries: run as a script, its own folder is on the path)."""
    if script == "vi_fmu_doc" and "vi_model_description" not in sys.modules:
        sys.modules["vi_model_description"] = load("vi_model_description")
    spec = importlib.util.spec_from_file_location(script, ROOT / "cmake" / f"{script}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ALL = [(name, v) for name in MODELS for v in (2, 3)]


# ---- licences --------------------------------------------------------------------------------------

def test_the_repository_has_a_licence_compatible_with_sundials():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("BSD 3-Clause License")
    assert "Redistributions in binary form must reproduce the above copyright notice" in text


@pytest.mark.timeout(30)
@pytest.mark.parametrize("name,version", ALL)
def test_every_fmu_carries_the_licences(name, version):
    with zipfile.ZipFile(fmu(name, version)) as z:
        names = set(z.namelist())
        licence = z.read("documentation/licenses/license.txt").decode("utf-8")
        assert (ROOT / "LICENSE").read_text() in licence
        if MODELS[name]:
            assert z.read("documentation/licenses/SUNDIALS.txt") == open(SUNDIALS_COPYRIGHT, "rb").read()
            assert "SUNDIALS.txt" in licence
            # the conditions SUNDIALS' licence asks a binary redistribution to reproduce
            sundials = z.read("documentation/licenses/SUNDIALS.txt").decode("utf-8")
            assert "Lawrence Livermore National Security" in sundials and "Additional BSD Notice" in sundials
        else:
            assert "documentation/licenses/SUNDIALS.txt" not in names


# ---- the documentation page --------------------------------------------------------------------------

class Page(html.parser.HTMLParser):
    """The ids, the link targets and the image sources of an HTML page."""

    def __init__(self):
        super().__init__()
        self.ids, self.links, self.images = set(), [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and "href" in a:
            self.links.append(a["href"])
        if tag == "img":
            self.images.append(a.get("src", ""))


def unresolved(z, entry):
    """The links and images of the page entry in the zip z that do not resolve inside it."""
    page = Page()
    page.feed(z.read(entry).decode("utf-8"))
    names, folder, bad = set(z.namelist()), posixpath.dirname(entry), []
    for kind, target in [("link", t) for t in page.links] + [("image", t) for t in page.images]:
        if kind == "link" and re.match(r"https?://", target):
            continue  # an absolute URL (fmpy's home page), not a file the FMU must hold
        path, _, anchor = target.partition("#")
        inside = posixpath.normpath(posixpath.join(folder, path)) if path else entry
        if ":" in path or inside.startswith("../") or inside not in names:
            bad.append(f"{kind} {target} (no {inside} in the FMU)")
        elif anchor and (inside != entry or anchor not in page.ids):
            bad.append(f"{kind} {target} (no id {anchor} in {inside})")
        elif kind == "image" and not z.read(inside).startswith(PNG_MAGIC):
            bad.append(f"image {target} is no PNG")
    return page, bad


@pytest.mark.timeout(30)
@pytest.mark.parametrize("name,version", ALL)
def test_every_link_and_image_of_the_page_resolves_inside_the_fmu(name, version):
    with zipfile.ZipFile(fmu(name, version)) as z:
        assert ENTRY[version] in z.namelist(), f"no {ENTRY[version]}: FMI {version}.0 names it the entry point"
        page, bad = unresolved(z, ENTRY[version])
    assert not bad, "\n".join(bad)
    assert "licenses/license.txt" in page.links


def test_the_link_check_sees_what_does_not_resolve(tmp_path):
    """The check above must fail a page with a dead link, a missing anchor, an image outside the FMU."""
    path = tmp_path / "x.zip"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("documentation/index.html", '<h1 id="top">x</h1><a href="#top">ok</a><a href="#gone">a</a>'
                   '<a href="../doc/model.md">b</a><img src="images/none.png"><a href="https://x.org">c</a>'
                   '<img src="images/text.png"><a href="file:///etc/passwd">d</a>')
        z.writestr("documentation/images/text.png", "not a png")
    with zipfile.ZipFile(path) as z:
        _, bad = unresolved(z, "documentation/index.html")
    assert [b.split()[1] for b in bad] == ["#gone", "../doc/model.md", "file:///etc/passwd", "images/none.png",
                                          "images/text.png"], bad


@pytest.mark.timeout(30)
@pytest.mark.parametrize("version", [2, 3])
def test_the_page_holds_the_reference_the_variables_and_the_version(version):
    path = fmu("VibroImpact", version)
    md = read_model_description(str(path))
    with zipfile.ZipFile(path) as z:
        text = z.read(ENTRY[version]).decode("utf-8")
    for heading in ("Using the FMU", "VibroImpact: the model and the FMU interface", "Guarantees to an importer"):
        assert heading in text
    assert ('id="fmi3-what-differs-from-the-fmi-20-fmu"' in text) == (version == 3)  # doc/fmi3.md, FMI 3.0 only
    table = text[text.index('<section id="variables">'):]
    rows = re.findall(r"<tr><td><code>([^<]+)</code></td><td>([0-9]+)</td>", table[:table.index("</section>")])
    expected = [(v.name, str(v.valueReference)) for v in md.modelVariables if v.valueReference < 2**30]
    assert rows == expected
    assert f"version {project_version()}" in text and md.generationDateAndTime in text


@pytest.mark.parametrize("name,version", ALL)
def test_the_model_description_carries_the_release(name, version):
    with zipfile.ZipFile(fmu(name, version)) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
        assert root.get("version") == project_version()
        assert XS_DATETIME_UTC.fullmatch(root.get("generationDateAndTime") or "")
        assert root.get("copyright") in (ROOT / "LICENSE").read_text().splitlines()
        assert "documentation/licenses/license.txt" in root.get("license")
        assert "documentation/licenses/license.txt" in z.namelist()


@pytest.mark.parametrize("version,where", [(2, "model.png"), (3, "terminalsAndIcons/icon.png")])
def test_the_fmu_has_the_icon_where_fmi_looks(version, where):
    with zipfile.ZipFile(fmu("VibroImpact", version)) as z:
        assert z.read(where) == (ROOT / "doc" / "icon.png").read_bytes()
    assert (ROOT / "doc" / "icon.png").read_bytes().startswith(PNG_MAGIC)


# ---- the stamp ---------------------------------------------------------------------------------------

@pytest.mark.timeout(30)
def test_the_stamp_honours_source_date_epoch(tmp_path):
    """SOURCE_DATE_EPOCH = 1700000000 s is 2023-11-14T22:13:20Z (19675 days and 80000 s after 1970-01-01);
    the environment wins over the value CMake saw, which wins over the clock."""
    script = ROOT / "cmake" / "vi_fmu_stamp.py"

    def date(env_epoch, configured):
        env = {"PATH": "/usr/bin:/bin"} | ({"SOURCE_DATE_EPOCH": env_epoch} if env_epoch is not None else {})
        out = tmp_path / "md.xml"
        run = subprocess.run([sys.executable, str(script), "--xml", str(ROOT / "modelDescription.xml"), "--version",
                              "9.8.7", f"--source-date-epoch={configured}", "--license", str(ROOT / "LICENSE"),
                              "--out", str(out)], env=env, capture_output=True, text=True, timeout=20)
        assert run.returncode == 0, run.stderr
        root = ET.parse(out).getroot()
        assert root.get("version") == "9.8.7"
        return root.get("generationDateAndTime")
    assert date("1700000000", "") == "2023-11-14T22:13:20Z"
    assert date("0", "1700000000") == "1970-01-01T00:00:00Z"
    assert date(None, "1700000000") == "2023-11-14T22:13:20Z"
    before = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    now = datetime.datetime.strptime(date(None, ""), "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=datetime.timezone.utc)
    assert before <= now <= datetime.datetime.now(datetime.timezone.utc)
    bad = subprocess.run([sys.executable, str(script), "--xml", str(ROOT / "modelDescription.xml"), "--version", "1",
                          "--license", str(ROOT / "LICENSE"), "--out", str(tmp_path / "x.xml")],
                         env={"SOURCE_DATE_EPOCH": "yesterday"}, capture_output=True, text=True, timeout=20)
    assert bad.returncode != 0 and "SOURCE_DATE_EPOCH='yesterday'" in bad.stderr


def test_the_stamp_replaces_attributes_and_keeps_every_other_byte():
    stamp = load("vi_fmu_stamp").stamp
    text = '<?xml version="1.0"?>\n<!-- a > b -->\n<fmiModelDescription a="x > y" version="1" b=\'2\'>\n<v/>\n' \
           '</fmiModelDescription>\n'
    assert stamp(text, {"version": "2.0.1", "license": 'BSD & "x"'}) == \
        '<?xml version="1.0"?>\n<!-- a > b -->\n<fmiModelDescription a="x > y" b=\'2\' version="2.0.1" ' \
        'license=\'BSD &amp; "x"\'>\n<v/>\n</fmiModelDescription>\n'


# ---- Markdown to HTML --------------------------------------------------------------------------------

def convert(tmp_path, markdown, **pages):
    doc = load("vi_fmu_doc")
    page = tmp_path / "doc" / "page.md"
    page.parent.mkdir(exist_ok=True)
    page.write_text(markdown)
    for other, text in pages.items():
        (page.parent / f"{other}.md").write_text(text)
    book = doc.Book(str(tmp_path / "out"), [str(page)] + [str(page.parent / f"{o}.md") for o in pages],
                    root=str(tmp_path))
    return doc.Converter(book, str(page), 1).convert(markdown.splitlines())


def test_markdown_blocks(tmp_path):
    md = ("# Title\n\nOne *two* **three** `a < b`\nfour.\n\n- x\n  more\n   - y\n- z\n\n1. first\n2. second\n\nText.\n\n"
          "    code & more\n\n```sh\nls | wc\n```\n\n| a | b |\n|---|---|\n| `x|y` | 2 |\n")
    assert convert(tmp_path, md) == "\n".join([
        '<h2 id="page-title">Title</h2>',
        "<p>One <em>two</em> <strong>three</strong> <code>a &lt; b</code> four.</p>",
        "<ul><li>x more<ul><li>y</li></ul></li><li>z</li></ul><ol><li>first</li><li>second</li></ol>",
        "<p>Text.</p>",
        "<pre><code>code &amp; more</code></pre>",
        "<pre><code>ls | wc</code></pre>",
        "<table><thead><tr><th>a</th><th>b</th></tr></thead><tbody><tr><td><code>x|y</code></td><td>2</td></tr>"
        "</tbody></table>"])


def test_markdown_links_stay_inside(tmp_path):
    """A link to a packed page goes to its anchor in this page; to anything else not packed, plain text
    (a file's name becomes its path in the repository)."""
    (tmp_path / "doc" / "fig.png").parent.mkdir()
    (tmp_path / "doc" / "fig.png").write_bytes(PNG_MAGIC)
    md = ("## A b\n## A b\n[x](#a-b) [other.md](other.md#c-d) [`src`](../src/x.c) [fmpy](https://fmpy.org) "
          "![p](fig.png) [numerics.md](numerics.md#solvers)\n")
    assert convert(tmp_path, md, other="# Other page\n## C d\n") == "\n".join([
        '<h3 id="page-a-b">A b</h3>', '<h3 id="page-a-b-1">A b</h3>',
        '<p><a href="#page-a-b">x</a> <a href="#other-c-d">other.md</a> <code>src</code> '
        '<a href="https://fmpy.org">fmpy</a> <img src="images/fig.png" alt="p"> doc/numerics.md</p>'])
    assert (tmp_path / "out" / "images" / "fig.png").read_bytes() == PNG_MAGIC


# ---- one version everywhere --------------------------------------------------------------------------

def test_citation_and_changelog_name_the_release():
    version = project_version()
    citation = (ROOT / "CITATION.cff").read_text()
    assert re.search(rf"^version: \"?{re.escape(version)}\"?$", citation, re.M)
    assert "Kowalska" in citation and "cff-version: 1.2.0" in citation
    assert re.search(rf"^## \[?{re.escape(version)}\]? ", (ROOT / "CHANGELOG.md").read_text(), re.M)


def test_the_wheel_declares_the_licence():
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert re.search(r'^license = "BSD-3-Clause"$', pyproject, re.M)
    assert re.search(r'^license-files = \["LICENSE"\]$', pyproject, re.M)
    assert "${SKBUILD_METADATA_DIR}/licenses" in (ROOT / "CMakeLists.txt").read_text()
