"""Profile files through the FMU in every interface: FMI 2.0 Co-Simulation and Model Exchange, FMI 3.0
Co-Simulation and Model Exchange.

A bad profile_file is refused at initialization (fmi2/fmi3ExitInitializationMode returns Error) with a
message naming profile_file, the file and the line, and saying what the line holds: decimal commas, a
header row, German decimals (decimal commas and semicolons), an empty file, a file of comments, x not
increasing, a value that is not finite, one row more than the cap (10 million), and a periodic wall too
steep for the doubles at its position (refused naming its rows, never as an internal error). A UTF-8
byte-order mark is skipped. A file with non-ASCII characters in its name, in a folder whose name has
non-ASCII characters and a blank, is found by an absolute path and through the resources folder, which
FMI 2.0 passes as a percent-encoded file URI (fmpy's pathlib.as_uri: %C3%BC, %20) and FMI 3.0 as a
path. With a = 0 and yC_in = 0 the output yC is the profile's yb at x0: a flat profile of height H
gives yC = H exactly, which shows that the file was read.
"""
import shutil

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

from conftest import BUILD
from vibroimpact.fmu import MessageLog, Messages

ERROR = 3  # fmi2Error and fmi3Error
ROWS_MAX = 10_000_000  # VI_PROFILE_ROWS_MAX of src/profile/vi_profile.h
FACES = ["fmi2-cs", "fmi2-me", "fmi3-cs", "fmi3-me"]
each_face = pytest.mark.parametrize("face", FACES)


class Log3(Messages):
    """The logger of an FMI 3.0 instance."""

    def log(self, env, status, category, message):
        self.keep(status, category, message.decode("utf-8", "replace"))


class Instance:
    """One instance of the FMU extracted into `where`, in the interface `face`: set(params) and
    init() (the raw status of ExitInitializationMode), its log in `log`."""

    def __init__(self, face, where):
        version, kind = face.split("-")
        self.v3 = version == "fmi3"
        fmu = BUILD / ("fmi3" if self.v3 else "") / "VibroImpact.fmu"
        md = read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.types = {v.name: v.type for v in md.modelVariables}
        self.dir = extract(str(fmu), unzipdir=str(where))
        ident = (md.coSimulation if kind == "cs" else md.modelExchange).modelIdentifier
        cls = {("fmi2", "cs"): FMU2Slave, ("fmi2", "me"): FMU2Model, ("fmi3", "cs"): FMU3Slave,
               ("fmi3", "me"): FMU3Model}[version, kind]
        self.s = cls(guid=md.guid, unzipDirectory=self.dir, modelIdentifier=ident, instanceName=face)
        if self.v3:
            self.log = Log3()
            self.s.instantiate(loggingOn=True, logMessage=self.log.log)
        else:
            self.log = MessageLog()
            self.s.instantiate(callbacks=self.log.callbacks, loggingOn=True)
            self.s.setupExperiment(startTime=0.0)

    def set(self, params):
        for name, value in params.items():
            t, vr = self.types[name], [self.vr[name]]
            if t == "String":
                self.s.setString(vr, [value])
            elif t == "Boolean":
                self.s.setBoolean(vr, [value])
            elif self.v3:
                self.s.setFloat64(vr, [value])
            else:
                self.s.setReal(vr, [value])

    def init(self, params):
        self.s.enterInitializationMode()
        self.set(params)
        fn = "fmi3ExitInitializationMode" if self.v3 else "fmi2ExitInitializationMode"
        return getattr(self.s.dll, fn)(self.s.component)  # the raw status: fmpy raises on Error

    def real(self, name):
        return (self.s.getFloat64 if self.v3 else self.s.getReal)([self.vr[name]])[0]

    def free(self):
        self.s.freeInstance()


def refused(face, tmp_path, params, *expect):
    """params refused at initialization with Error and a message naming profile_file with every text of expect."""
    inst = Instance(face, tmp_path / "fmu")
    status = inst.init(params)
    text = inst.log.text()
    inst.free()
    assert status == ERROR, (status, text)
    assert any("profile_file" in m and all(e in m for e in expect) for m in inst.log.texts()), text
    return text


HOW = ("write x and h in the C syntax with '.' decimals (0.5, -1.2e-3) separated by blanks, a tab, one comma or one semicolon; "
       "lines starting with # are comments")

BAD = {
    "decimal commas": ("0,5\n1,5\n2,5\n", ", line 1: expected two numbers x [m] and h [m], found 1 field '0,5' (separator: "
                       "none): a comma is no decimal point, and '0,5' could be 0.5 or the columns 0 and 5; " + HOW),
    "header": ("x h\n0 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields 'x' 'h' (separator: "
               "blanks): 'x' is not a number (a header? start it with #); " + HOW),
    "German decimals": ("# x;h\n0;0\n1,5;2,5\n", ", line 3: expected two numbers x [m] and h [m], found 2 fields '1,5' "
                        "'2,5' (separator: a semicolon): a comma is no decimal point"),
    "empty": ("", ": the file is empty; a profile needs at least two rows x [m] h [m]"),
    "comments only": ("# x h\n\n# nothing\n", ": no data rows, its 3 lines are blank or comments"),
    "x not increasing": ("0 0\n2 0\n\n1 0\n", ", line 4: x = 1 is not greater than x = 2 on line 2 (x must increase)"),
    "not finite": ("0 0\n1 1e400\n", ", line 2: x = 1, h = inf: h is not finite"),
}


@each_face
@pytest.mark.parametrize("case", list(BAD))
def test_bad_files_are_refused_saying_what_they_hold(face, case, tmp_path):
    text, expect = BAD[case]
    path = tmp_path / "bad.txt"
    path.write_text(text)
    refused(face, tmp_path, dict(profile_file=str(path), V=1.0), f"'{path}'{expect}")


@pytest.fixture(scope="module")
def too_many_rows(tmp_path_factory):
    """A file of ROWS_MAX + 1 rows (x = 0, 1, 2, ..., h = 0) after one comment line."""
    path = tmp_path_factory.mktemp("cap") / "rows.txt"
    with open(path, "w") as f:
        f.write("# one row more than the cap\n")
        step = 1_000_000
        for a in range(0, ROWS_MAX + 1, step):
            f.write("".join(f"{i} 0\n" for i in range(a, min(a + step, ROWS_MAX + 1))))
    yield path
    path.unlink()


@each_face
def test_more_rows_than_the_cap_are_refused(face, tmp_path, too_many_rows):
    refused(face, tmp_path, dict(profile_file=str(too_many_rows), V=1.0),
            f"'{too_many_rows}', line {ROWS_MAX + 2}: more than {ROWS_MAX} rows, the most a profile may have")


@each_face
def test_a_periodic_wall_too_steep_for_doubles_is_refused_naming_its_rows(face, tmp_path):
    """The three-row periodic table with R1 = 1.217226034797203e-06 m: its wall (rows 2 and 3, slope
    1.1749 m / 48.7 um = 24131) is left 1e-15 m before its top, below the spacing of doubles at 16.48 m."""
    path = tmp_path / "steep.txt"
    path.write_text("-0.46331928351137353 3.3603288399901734\n16.478735101136888 2.1854535280021321\n"
                    "16.478783788505101 3.3603288399901734\n")
    text = refused(face, tmp_path, dict(profile_file=str(path), V=1.0, R1=1.217226034797203e-06, profile_periodic=True),
                   "rows 2 and 3 (x = 16.478735101136888 and 16.478783788505101 m) make a slope of 24131, too steep")
    assert "internal error" not in text


H = 2.5e-4  # the height of the flat profiles below [m]


def rolled(face, where, profile_file):
    """yC after initialization over profile_file (flat at H), and the log."""
    inst = Instance(face, where)
    status = inst.init(dict(profile_file=profile_file, V=1.0, x0=0.5))
    y = inst.real("yC") if status == 0 else None
    text = inst.log.text()
    inst.free()
    assert status == 0, text
    return y


@each_face
def test_a_utf8_byte_order_mark_is_skipped(face, tmp_path):
    path = tmp_path / "bom.txt"
    path.write_bytes(b"\xef\xbb\xbf# x h\r\n0 2.5e-4\r\n1 2.5e-4\r\n")
    assert rolled(face, tmp_path / "fmu", str(path)) == H


@each_face
def test_non_ascii_paths_and_a_percent_encoded_resource_uri(face, tmp_path, monkeypatch):
    """The FMU unpacked into 'Prüf stand' (FMI 2.0 gets its resources as file:///.../Pr%C3%BCf%20stand/resources),
    the profile 'Schiene_ü.txt' in its resources folder, named relative; and the same file by its absolute
    path. The working directory holds a file of that name with another height: the resources' is taken."""
    where = tmp_path / "Prüf stand"
    inst_dir = where / "fmu"
    # unpack once to find the resources folder, then put the profile there
    Instance(face, inst_dir).free()
    resources = inst_dir / "resources"
    resources.mkdir(exist_ok=True)
    (resources / "Schiene_ü.txt").write_text(f"0 {H!r}\n1 {H!r}\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "Schiene_ü.txt").write_text("0 0\n1 0\n", encoding="utf-8")
    assert "Pr%C3%BCf%20stand" in resources.as_uri()  # what fmpy passes to fmi2Instantiate
    assert rolled(face, inst_dir, "Schiene_ü.txt") == H
    assert rolled(face, inst_dir, str(resources / "Schiene_ü.txt")) == H
    shutil.rmtree(where)
