"""How the commands fail: one line that names what was wrong and what to do, never a traceback.

A command raises CommandError with that line; the command line (vibroimpact.cli) prints it after the command's
name and exits 1 (`vibroimpact --debug COMMAND` shows the traceback instead). fmu_refused turns a
failed FMI call into that line with what the FMU logged.
"""
import pathlib


class CommandError(Exception):
    """What a command cannot do, said in one line (what was wrong, what to do)."""


def fmu_refused(what, exc, messages):
    """A CommandError for an FMI call that failed (exc) while doing `what`: the FMU's own messages
    (its reason, naming the variable and its range) when it logged any, else the exception."""
    said = "; ".join(m.strip() for m in messages if m.strip())
    return CommandError(f"{what}: {said or exc}")


def out_dir(path, option="--out"):
    """The output folder `path`, created when missing; a CommandError when it names a file."""
    path = pathlib.Path(path)
    if path.exists() and not path.is_dir():
        raise CommandError(f"{option} {path} is a file: name a folder (it is created when missing)")
    path.mkdir(parents=True, exist_ok=True)
    return path


def describe(exc):
    """The one line the command line prints for an exception a command did not turn into a CommandError."""
    if isinstance(exc, CommandError):
        return str(exc)
    if isinstance(exc, FileNotFoundError) and exc.filename is None:
        return str(exc)   # fmu_path's message: what is missing and how to get it
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.strerror}: {exc.filename}" if exc.filename else exc.strerror
    return f"{type(exc).__name__}: {exc} (not expected here: `vibroimpact --debug ...` shows where it came from)"
