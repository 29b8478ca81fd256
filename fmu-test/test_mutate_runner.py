"""tools/mutate.py's way of running a command: a command past its time limit is killed with every
process it started, also those in a session of their own (as ctest starts each test)."""
import importlib.util
import pathlib
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def load_mutate():
    spec = importlib.util.spec_from_file_location("mutate_tool", ROOT / "tools" / "mutate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def running(pid):
    """Is pid a process that has not ended (a zombie has)?"""
    try:
        state = pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


def test_a_command_past_its_limit_leaves_no_process_behind(tmp_path):
    mutate = load_mutate()
    pids = tmp_path / "pids"
    # a child in a session of its own (setsid) and a grandchild of it, both sleeping past the limit
    script = f"setsid bash -c 'sleep 300 & echo $! >> {pids}; wait' & echo $! >> {pids}; wait"
    t0 = time.monotonic()
    status, _ = mutate.run(["bash", "-c", script], tmp_path, timeout=2)
    assert status == "timeout"
    assert time.monotonic() - t0 < 60
    started = [int(p) for p in pids.read_text().split()]
    assert len(started) == 2
    for _ in range(100):  # SIGKILL is delivered at once; the wait is for the kernel to tear them down
        if not any(running(p) for p in started):
            break
        time.sleep(0.05)
    assert not [p for p in started if running(p)], "still running after the timeout"


def test_a_command_within_its_limit_gives_its_status_and_output(tmp_path):
    status, out = load_mutate().run(["bash", "-c", "echo done; exit 3"], tmp_path, timeout=60)
    assert (status, out) == (3, "done\n")
