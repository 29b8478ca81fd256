"""Stamp a generated modelDescription.xml (FMI 2.0 or 3.0) with the release: version, generation date, copyright
and licence. Run at build time by vi_add_fmu (cmake/vi_fmu.cmake):

    python vi_fmu_stamp.py --xml modelDescription.xml --version VERSION --license LICENSE --out OUT.xml
                           [--generation-tool TEXT]

VERSION is the CMake project's version (project(... VERSION) in CMakeLists.txt, which pyproject.toml reads
too). generationDateAndTime is SOURCE_DATE_EPOCH (seconds since 1970, UTC; reproducible builds): the
environment variable when it is set, else --source-date-epoch (its value when CMake configured the
build) when that is not empty, else the current time. copyright is the "Copyright" line of LICENSE, and
license names LICENSE's title (its first line) and where the FMU holds the licences. --generation-tool
replaces generationTool, to say what the binaries were built with (vi_add_fmu's GENERATION_TOOL: the
SUNDIALS they carry).

The root element's attributes of those names are replaced or added; every other byte of the file stays
as generated (comments included), so that the stamped file differs from the generated one in the root
element's start tag only.
"""
import argparse
import datetime
import os
import re
import sys
import xml.etree.ElementTree as ET
from xml.sax.saxutils import quoteattr

# Where the packed FMU holds the licence texts (vi_add_fmu puts them there).
LICENSE_ENTRY = "documentation/licenses/license.txt"
# The root element's start tag; attribute values may hold '>' and '/'.
ROOT_TAG = re.compile(r"<fmiModelDescription((?:\s+[\w:.-]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)(\s*)>")
ATTRIBUTE = re.compile(r"(\s+)([\w:.-]+)(\s*=\s*(?:\"[^\"]*\"|'[^']*'))")


def fail(msg):
    sys.exit(f"vi_fmu_stamp.py: {msg}")


def generation_date(epoch):
    """xs:dateTime in UTC of epoch (seconds since 1970, text), or of now when it is empty."""
    epoch = epoch.strip()
    if epoch and not epoch.isdigit():
        fail(f"SOURCE_DATE_EPOCH={epoch!r} is not a number of seconds since 1970-01-01 UTC")
    moment = datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc) if epoch else \
        datetime.datetime.now(datetime.timezone.utc)
    return moment.strftime("%Y-%m-%dT%H:%M:%SZ")


def license_attributes(license_text):
    """(copyright, license) of the model description from the text of LICENSE."""
    lines = [ln.strip() for ln in license_text.splitlines() if ln.strip()]
    holder = next((ln for ln in lines if ln.startswith("Copyright")), None)
    if not lines or holder is None:
        fail("LICENSE has no title line or no 'Copyright' line")
    return holder, f"{lines[0]}; the licences of the FMU and of the code its binaries carry: {LICENSE_ENTRY}"


def stamp(text, values):
    """text with the root element's attributes of the names in values replaced or appended."""
    m = ROOT_TAG.search(text)
    if m is None:
        fail("no <fmiModelDescription ...> start tag")
    kept = "".join(a.group(0) for a in ATTRIBUTE.finditer(m.group(1)) if a.group(2) not in values)
    added = "".join(f" {k}={quoteattr(v)}" for k, v in values.items())
    return text[:m.start()] + f"<fmiModelDescription{kept}{added}{m.group(2)}>" + text[m.end():]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--xml", required=True, help="the generated modelDescription.xml")
    ap.add_argument("--version", required=True, help="the release version (CMake's PROJECT_VERSION)")
    ap.add_argument("--license", required=True, help="the repository's LICENSE")
    ap.add_argument("--out", required=True, help="the stamped modelDescription.xml to write")
    ap.add_argument("--source-date-epoch", default="", help="SOURCE_DATE_EPOCH when the environment has none")
    ap.add_argument("--generation-tool", default="", help="the generationTool attribute (empty: the generator's)")
    args = ap.parse_args()
    with open(args.xml, encoding="utf-8") as f:
        text = f.read()
    with open(args.license, encoding="utf-8") as f:
        holder, licence = license_attributes(f.read())
    values = dict(version=args.version, generationDateAndTime=generation_date(os.environ.get("SOURCE_DATE_EPOCH") or args.source_date_epoch),
                  copyright=holder, license=licence)
    if args.generation_tool:
        values["generationTool"] = args.generation_tool
    out = stamp(text, values)
    root = ET.fromstring(out.encode("utf-8"))
    if root.tag != "fmiModelDescription" or any(root.get(k) != v for k, v in values.items()):
        fail(f"{args.xml}: the stamped root element does not read back as {values}")
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(out)


if __name__ == "__main__":
    main()
