"""The set-up by purpose (tools/setup.sh): the main command (tools/main.sh) installs what the main job uses
and nothing else, the test command (tools/test.sh) adds what the tests use and says so.

What the main job uses is the README's list: a C compiler, make, CMake, SUNDIALS and Python with the
package's own dependencies; no Rust, no test tool. The tests add Criterion, valgrind, clang, the locales,
the cross compilers with wine64 and qemu-user, zig, the package's test extra and fmi-sim. On a machine
with no Rust (a fresh HOME, Debian's own programs on the PATH, curl and rustup replaced by programs that
record a call), a dry run of the main set-up never mentions Rust nor calls them; the tests' says why Rust
comes from rustup (Debian 12's rustc is older than the 1.85 fmi-sim 0.7 needs) or installs Debian's."""
import re
import subprocess
import sys

from conftest import ROOT

SETUP = ROOT / "tools" / "setup.sh"
MAIN_APT = {"gcc", "make", "cmake", "libsundials-dev", "python3"}
RUST_MIN = (1, 85)  # edition 2024, which fmi-sim 0.7.0 is written in


def listed(*options):
    """{kind: [items]} of `setup.sh <options> --list`."""
    run = subprocess.run([str(SETUP), *options, "--list"], capture_output=True, text=True, timeout=30, check=True)
    return {k: v.split() for k, v in (line.split(":", 1) for line in run.stdout.splitlines())}


def test_the_main_setup_installs_what_the_main_job_uses_and_nothing_else():
    main = listed()
    assert set(main["apt"]) == MAIN_APT
    assert "vibroimpact" in main["pip"]
    assert not any("[" in p for p in main["pip"]), "no extra of the package (the test extra is the tests')"
    assert main["cargo"] == [] and main["locales"] == []


def test_the_test_setup_adds_what_the_tests_use():
    main, test = listed(), listed("--test")
    assert set(main["apt"]) < set(test["apt"])
    for package in ("libcriterion-dev", "valgrind", "clang", "libclang-rt-14-dev", "locales", "wine64", "qemu-user",
                    "gcc-mingw-w64-x86-64", "gcc-aarch64-linux-gnu"):
        assert package in test["apt"], package
    assert "vibroimpact[test]" in test["pip"] and any(p.startswith("ziglang==") for p in test["pip"])
    assert test["cargo"] == ["fmi-sim=fmi-sim@0.7.0"] and set(test["locales"]) == {"de_DE", "ps_AF"}
    # the release's needs are the tests' too (tools/cross_test.sh runs tools/release.sh)
    assert set(listed("--release")["apt"]) <= set(test["apt"])
    # the vehicle-track example adds its second master only
    example = listed("--example")
    assert example["apt"] == main["apt"] and set(example["pip"]) - set(main["pip"]) == {"libcosimpy"}
    assert example["cargo"] == []


def fresh_machine(tmp_path):
    """The environment of a machine with no Rust: a fresh HOME, Debian's own programs, and curl and rustup
    that only record that they were called (in tmp_path/called)."""
    stubs = tmp_path / "stubs"
    stubs.mkdir()
    for program in ("curl", "rustup"):
        (stubs / program).write_text(f"#!/bin/sh\necho {program} >>{tmp_path / 'called'}\nexit 1\n")
        (stubs / program).chmod(0o755)
    home = tmp_path / "home"
    home.mkdir()
    return {"HOME": str(home), "PATH": f"{stubs}:/usr/sbin:/usr/bin:/sbin:/bin", "PYTHON": sys.executable}


def dry_run(tmp_path, *options):
    run = subprocess.run([str(SETUP), *options, "--dry-run"], capture_output=True, text=True, timeout=60,
                         env=fresh_machine(tmp_path))
    assert run.returncode == 0, run.stderr
    assert not (tmp_path / "called").exists(), (tmp_path / "called").read_text()
    return run.stderr


def test_the_main_setup_never_reaches_rust(tmp_path):
    said = dry_run(tmp_path)
    assert not re.search(r"rust|cargo|fmi-sim|curl", said, re.I), said


def test_the_test_setup_says_where_rust_comes_from_and_why(tmp_path):
    said = dry_run(tmp_path, "--test")
    policy = subprocess.run(["apt-cache", "policy", "rustc"], capture_output=True, text=True, timeout=30).stdout
    candidate = re.search(r"Candidate: (\d+)\.(\d+)", policy)
    if candidate and tuple(map(int, candidate.groups())) >= RUST_MIN:
        assert re.search(r"\(for the tests\): would apt-get install .*\bcargo rustc\b", said), said
    else:
        assert "(for the tests): fmi-sim needs Rust 1.85 or later (edition 2024)" in said, said
        assert "Rust comes from rustup" in said and "would rustup" in said, said
    assert "(for the tests): would cargo install fmi-sim@0.7.0" in said, said
