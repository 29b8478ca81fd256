"""Write the documentation/ folder of an FMU: one self-contained HTML page and the licences.

Run at build time by vi_add_fmu (cmake/vi_fmu.cmake):

    python vi_fmu_doc.py --fmi 2|3 --xml modelDescription.xml --license LICENSE [--notice NAME=FILE ...]
                         [--intro README.md] [--page PAGE.md ...] --out DIR --dump [EMULATOR...] DUMP

Writes into DIR (the FMU's documentation/ folder):
  _main.html (FMI 2.0) or index.html (FMI 3.0), the entry point the standard names: the model's name,
      version and generation date (from the stamped model description, cmake/vi_fmu_stamp.py), the
      part of --intro before its first second-level heading, each --page in full, the variable table
      (the output of DUMP, tests/dump_variables.c: the one table the model descriptions come from too)
      and the licences;
  images/  every image a page shows, copied beside the page;
  licenses/license.txt  the entry point of the licence information (FMI 3.0 names it): LICENSE, and
      for each --notice the third-party code the binaries carry; licenses/NAME.txt the text of FILE
      (copied at build time from where the third party ships it, e.g. Debian's copyright file).

Markdown to HTML covers what the repository's pages use: headings, paragraphs, fenced and indented
code, lists (nested by indentation), pipe tables, inline code, **bold**, *italic*, links and images.
A link to a page packed here becomes a link into this page (every heading gets an id: the page's
name and GitHub's anchor of the heading); a link to anything else that is not packed (a source file,
another page of the repository) becomes its plain text (a file's name: its path in the repository),
so that every link resolves inside the FMU or is an absolute URL.
"""
import argparse
import html
import os
import re
import shutil
import sys
import xml.etree.ElementTree as ET

import vi_model_description as mdgen  # beside this script: the reader of the table dump

ENTRY = {"2": "_main.html", "3": "index.html"}
LICENSES = "licenses"
IMAGES = "images"
# GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens (as fmu-test/test_docs.py).
DROPPED = re.compile(r"[^\w\- ]")
CODE_SPAN = re.compile(r"`([^`\n]+)`")
IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)")
LINK = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")
BOLD = re.compile(r"\*\*(.+?)\*\*")
ITALIC = re.compile(r"(?<![\w*])\*(?![\s*])(.+?)(?<![\s*])\*(?![\w*])")
HEADING = re.compile(r"(#{1,6}) +(.*?) *#*$")
ITEM = re.compile(r"( *)([-*]|\d+\.) +(.*)")
TABLE_RULE = re.compile(r"\|? *:?-+:? *(\| *:?-+:? *)*\|? *$")
SCHEME = re.compile(r"[a-z][a-z0-9+.-]*:")


def fail(msg):
    sys.exit(f"vi_fmu_doc.py: {msg}")


def slug(heading):
    return DROPPED.sub("", heading.strip().lower()).replace(" ", "-")


class Book:
    """The pages packed into one HTML page: where each Markdown file's anchors go, and the images."""

    def __init__(self, out_dir, files, root=None):
        self.out_dir = out_dir
        self.root = root   # the repository: a link to a file of it that is not packed names its path
        self.ids = {os.path.abspath(f): self.page_id(f) for f in files}
        self.titles = {}   # absolute path -> the page's title, for a link whose text is the file's name
        self.images = {}   # absolute source path -> path in documentation/

    @staticmethod
    def page_id(path):
        return slug(os.path.splitext(os.path.basename(path))[0])

    def link(self, page, target):
        """href of a link on page (a Markdown file), or None when the target is not packed."""
        if SCHEME.match(target):
            return target
        path, _, anchor = target.partition("#")
        dest = os.path.abspath(os.path.join(os.path.dirname(page), path)) if path else os.path.abspath(page)
        if dest not in self.ids:
            return None
        return f"#{self.ids[dest]}-{anchor}" if anchor else f"#{self.ids[dest]}"

    def image(self, page, target):
        """src of an image on page: copied into images/ (an absolute URL is kept)."""
        if SCHEME.match(target):
            return target
        source = os.path.abspath(os.path.join(os.path.dirname(page), target))
        if not os.path.isfile(source):
            fail(f"{page}: image {target} not found")
        if source not in self.images:
            name = os.path.basename(source)
            if name in {os.path.basename(p) for p in self.images.values()}:
                name = f"{len(self.images)}-{name}"
            self.images[source] = f"{IMAGES}/{name}"
            os.makedirs(os.path.join(self.out_dir, IMAGES), exist_ok=True)
            shutil.copyfile(source, os.path.join(self.out_dir, IMAGES, name))
        return self.images[source]


def inline(text, book, page):
    """One line or paragraph of Markdown inline syntax as HTML."""
    spans = []

    def keep(html_text):
        spans.append(html_text)
        return f"\x00{len(spans) - 1}\x00"
    text = CODE_SPAN.sub(lambda m: keep(f"<code>{html.escape(m.group(1))}</code>"), text)
    text = IMAGE.sub(lambda m: keep(f'<img src="{html.escape(book.image(page, m.group(2)))}" '
                                    f'alt="{html.escape(m.group(1))}">'), text)

    def link(m):
        href = book.link(page, m.group(2))
        path = os.path.abspath(os.path.join(os.path.dirname(page), m.group(2).partition("#")[0]))
        text = m.group(1)
        if text == os.path.basename(path) and href:
            text = book.titles.get(path, text)
        elif text == os.path.basename(path) and book.root and path.startswith(os.path.join(book.root, "")):
            text = os.path.relpath(path, book.root)
        label = restore(html.escape(text, quote=False))
        return keep(f'<a href="{html.escape(href)}">{label}</a>' if href else label)

    def restore(s):
        return re.sub("\x00([0-9]+)\x00", lambda m: spans[int(m.group(1))], s)
    text = LINK.sub(link, text)
    text = html.escape(text, quote=False)
    text = BOLD.sub(r"<strong>\1</strong>", text)
    text = ITALIC.sub(r"<em>\1</em>", text)
    for _ in range(len(spans) + 1):  # a span may hold another (a code span in a link's text)
        if "\x00" not in text:
            break
        text = restore(text)
    return text


def table_cells(line):
    """The cells of a pipe-table row; a pipe inside a code span or escaped is part of the cell."""
    cells, cell, in_code, i = [], "", False, 0
    line = line.strip()
    line = line[1:] if line.startswith("|") else line
    while i < len(line):
        c = line[i]
        if c == "\\" and line[i + 1:i + 2] == "|":
            cell, i = cell + "|", i + 2
            continue
        if c == "`":
            in_code = not in_code
        if c == "|" and not in_code:
            cells.append(cell.strip())
            cell = ""
        else:
            cell += c
        i += 1
    if cell.strip():
        cells.append(cell.strip())
    return cells


def list_html(items, book, page):
    """Nested <ul>/<ol> from (indent, ordered, text) items."""
    out, stack = [], []  # stack of (indent, tag)
    for indent, ordered, text in items:
        tag = "ol" if ordered else "ul"
        while stack and indent < stack[-1][0]:
            out.append(f"</li></{stack.pop()[1]}>")
        if stack and indent == stack[-1][0] and tag != stack[-1][1]:  # another kind of list starts
            out.append(f"</li></{stack.pop()[1]}>")
        if not stack or indent > stack[-1][0]:
            out.append(f"<{tag}>")
            stack.append((indent, tag))
        else:
            out.append("</li>")
        out.append(f"<li>{inline(text, book, page)}")
    while stack:
        out.append(f"</li></{stack.pop()[1]}>")
    return "".join(out)


class Converter:
    """The blocks of one Markdown page, as HTML, with headings shifted down by `shift` levels."""

    def __init__(self, book, page, shift):
        self.book, self.page, self.shift = book, page, shift
        self.prefix = book.ids[os.path.abspath(page)]
        self.seen = {}
        self.out = []

    def heading(self, level, text):
        s = slug(text)
        n = self.seen.get(s, 0)
        self.seen[s] = n + 1
        anchor = f"{self.prefix}-{s if n == 0 else f'{s}-{n}'}"
        level = min(level + self.shift, 6)
        self.out.append(f'<h{level} id="{html.escape(anchor)}">{inline(text, self.book, self.page)}</h{level}>')

    def table(self, rows):
        head, body = table_cells(rows[0]), [table_cells(r) for r in rows[2:]]
        cell = lambda tag, c: f"<{tag}>{inline(c, self.book, self.page)}</{tag}>"  # noqa: E731
        self.out.append("<table><thead><tr>" + "".join(cell("th", c) for c in head) + "</tr></thead><tbody>" +
                        "".join("<tr>" + "".join(cell("td", c) for c in r) + "</tr>" for r in body) +
                        "</tbody></table>")

    def convert(self, lines):
        i = 0
        while i < len(lines):  # each pass consumes at least one line
            i = self.block(lines, i)
        return "\n".join(self.out)

    def block(self, lines, i):
        """Convert the block that starts at line i; the index of the line after it."""
        line = lines[i]
        if not line.strip():
            return i + 1
        if line.startswith("```"):
            end = next((j for j in range(i + 1, len(lines)) if lines[j].startswith("```")), len(lines))
            self.out.append(f"<pre><code>{html.escape(chr(10).join(lines[i + 1:end]))}</code></pre>")
            return end + 1
        m = HEADING.match(line)
        if m:
            self.heading(len(m.group(1)), m.group(2))
            return i + 1
        if line.startswith("    "):
            end = next((j for j in range(i, len(lines)) if lines[j].strip() and not lines[j].startswith("    ")),
                       len(lines))
            while not lines[end - 1].strip():
                end -= 1
            self.out.append(f"<pre><code>{html.escape(chr(10).join(ln[4:] for ln in lines[i:end]))}</code></pre>")
            return end
        if line.lstrip().startswith("|") and i + 1 < len(lines) and TABLE_RULE.match(lines[i + 1].strip()):
            end = next((j for j in range(i, len(lines)) if not lines[j].lstrip().startswith("|")), len(lines))
            self.table(lines[i:end])
            return end
        if ITEM.match(line):
            return self.items(lines, i)
        end = i + 1
        while end < len(lines) and lines[end].strip() and not self.starts_block(lines[end]):
            end += 1
        self.out.append(f"<p>{inline(' '.join(ln.strip() for ln in lines[i:end]), self.book, self.page)}</p>")
        return end

    @staticmethod
    def starts_block(line):
        return bool(line.startswith("```") or HEADING.match(line) or ITEM.match(line) or line.lstrip().startswith("|"))

    def items(self, lines, i):
        """A list: items and their indented continuation lines, up to a line that is neither."""
        items = []
        while i < len(lines):
            m = ITEM.match(lines[i])
            if m:
                items.append([len(m.group(1)), m.group(2)[0].isdigit(), m.group(3)])
            elif lines[i].strip() and (lines[i].startswith(" ") or not self.starts_block(lines[i])):
                items[-1][2] += " " + lines[i].strip()
            elif not lines[i].strip() and i + 1 < len(lines) and \
                    (ITEM.match(lines[i + 1]) or lines[i + 1].startswith("  ")):
                pass  # a blank line between items
            else:
                break
            i += 1
        self.out.append(list_html(items, self.book, self.page))
        return i


def intro_lines(path):
    """The lines of a README before its first second-level heading, without its title."""
    lines = open(path, encoding="utf-8").read().splitlines()
    end = next((i for i, ln in enumerate(lines) if ln.startswith("## ")), len(lines))
    return [ln for ln in lines[:end] if not ln.startswith("# ")]


def variable_table(dump, fmi):
    """The variables of the dump as an HTML table, with the types of the FMI version."""
    _, variables, items = mdgen.read_table(dump)
    types3 = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
    rows = []
    for v in variables:
        kind = v["type"] if fmi == "2" else ("Enumeration" if v["enum"] != "none" else types3[v["type"]])
        bounds = [mdgen.number(b) if b else "" for b in (v["min"], v["max"])]
        start = "" if v["initial"] == "calculated" else (v["start"] if v["type"] == "String" else
                                                         mdgen.number(v["start"]))
        cells = [f"<code>{html.escape(v['name'])}</code>", str(v["vr"]), kind, v["causality"], v["variability"],
                 html.escape(start), html.escape(bounds[0]), html.escape(bounds[1]), html.escape(v["unit"]),
                 html.escape(v["description"])]
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    head = ["name", "value reference", "type", "causality", "variability", "start", "min", "max", "unit",
            "description"]
    enum_note = ""
    if fmi == "3" and items:
        enum_note = "<p>Enumeration items: " + "; ".join(
            f"<code>{html.escape(t)}</code>: " + ", ".join(f"{html.escape(n)}={k}" for n, k in its)
            for t, its in items.items()) + ".</p>"
    return ("<table><thead><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr></thead><tbody>" +
            "".join(rows) + "</tbody></table>" + enum_note)


def write_licenses(out_dir, license_file, notices, model):
    """licenses/license.txt and licenses/<NAME>.txt; the text of license.txt."""
    os.makedirs(os.path.join(out_dir, LICENSES), exist_ok=True)
    parts = [f"{model} is distributed under the licence below (the repository's LICENSE).\n",
             open(license_file, encoding="utf-8").read().rstrip("\n") + "\n"]
    for name, source in notices:
        shutil.copyfile(source, os.path.join(out_dir, LICENSES, f"{name}.txt"))
        parts.append(f"The binaries of this FMU contain code of {name}, linked statically. Its copyright and "
                     f"licence, whose conditions apply to that code: {name}.txt in this folder (copied from "
                     f"{source}).\n")
    text = "\n".join(parts)
    with open(os.path.join(out_dir, LICENSES, "license.txt"), "w", encoding="utf-8") as f:
        f.write(text)
    return text


def page_html(md, sections, fmi):
    name, version, date = md.get("modelName"), md.get("version"), md.get("generationDateAndTime")
    toc = "".join(f'<li><a href="#{sid}">{html.escape(title)}</a></li>' for sid, title, _ in sections)
    body = "\n".join(f'<section id="{sid}">\n{content}\n</section>' for sid, _, content in sections)
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{html.escape(name)} {html.escape(version or "")}</title>
<style>
body {{ font-family: sans-serif; max-width: 60em; margin: 1em auto; padding: 0 1em; line-height: 1.45; }}
table {{ border-collapse: collapse; margin: 0.5em 0; }} th, td {{ border: 1px solid #bbb; padding: 0.2em 0.4em;
vertical-align: top; }} pre {{ background: #f4f4f4; padding: 0.5em; overflow-x: auto; }}
img {{ max-width: 100%; }} code {{ background: #f4f4f4; }}
</style>
</head>
<body>
<h1>{html.escape(name)} {html.escape(version or "")}</h1>
<p>FMI {fmi}.0 FMU, version {html.escape(version or "")}, generated {html.escape(date or "")}.</p>
<ul>{toc}</ul>
{body}
</body>
</html>
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmi", required=True, choices=sorted(ENTRY), help="the FMI version of the FMU")
    ap.add_argument("--xml", required=True, help="the FMU's (stamped) modelDescription.xml")
    ap.add_argument("--license", required=True, help="the repository's LICENSE")
    ap.add_argument("--notice", action="append", default=[], metavar="NAME=FILE",
                    help="third-party code the binaries carry, and the file of its copyright and licence")
    ap.add_argument("--intro", help="a README whose part before the first '## ' heading opens the page")
    ap.add_argument("--page", action="append", default=[], help="a Markdown page packed in full")
    ap.add_argument("--out", required=True, help="the documentation/ folder to write")
    ap.add_argument("--dump", required=True, nargs="+", help="the command that prints the variable table")
    args = ap.parse_args()

    notices = [tuple(n.split("=", 1)) for n in args.notice]
    for n in notices:
        if len(n) != 2 or not re.fullmatch(r"[\w.-]+", n[0]) or not os.path.isfile(n[1]):
            fail(f"--notice {'='.join(n)}: give NAME=FILE with an existing FILE")
    md = ET.parse(args.xml).getroot()
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    book = Book(args.out, ([args.intro] if args.intro else []) + args.page,
                root=os.path.dirname(os.path.abspath(args.license)))  # the repository holds LICENSE
    sections = []
    pages = {page: open(page, encoding="utf-8").read().splitlines() for page in args.page}
    for page, lines in pages.items():
        book.titles[os.path.abspath(page)] = next((HEADING.match(ln).group(2) for ln in lines if HEADING.match(ln)),
                                                  book.page_id(page))
    if args.intro:
        sections.append((book.page_id(args.intro), "Overview", "<h2>Overview</h2>\n" +
                         Converter(book, args.intro, 1).convert(intro_lines(args.intro))))
    for page, lines in pages.items():
        sections.append((book.page_id(page), book.titles[os.path.abspath(page)],
                         Converter(book, page, 1).convert(lines)))
    sections.append(("variables", "Variables", "<h2>Variables</h2>\n<p>Every variable of the model description, "
                     "from the model's variable table.</p>\n" + variable_table(args.dump, args.fmi)))
    licence = write_licenses(args.out, args.license, notices, md.get("modelName"))
    links = "".join(f'<li><a href="{LICENSES}/{n}.txt">{html.escape(n)}</a></li>' for n, _ in notices)
    sections.append(("licenses", "Licences", f'<h2>Licences</h2>\n<p><a href="{LICENSES}/license.txt">'
                     f'{LICENSES}/license.txt</a>:</p>\n<pre>{html.escape(licence)}</pre>\n<ul>{links}</ul>'))
    if len({sid for sid, _, _ in sections}) != len(sections):
        fail(f"two sections share an id: {[sid for sid, _, _ in sections]}")
    with open(os.path.join(args.out, ENTRY[args.fmi]), "w", encoding="utf-8") as f:
        f.write(page_html(md, sections, args.fmi))


if __name__ == "__main__":
    main()
