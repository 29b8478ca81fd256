"""The vehicle-track example on the FMI 3.0 FMUs (examples/vehicle-track/master3.py): the early-return
master against the monolithic reference, and against master.py on the FMI 2.0 FMUs."""
import numpy as np
import pytest

import master
import master3
import study

# The contact FMU's internal excitation strong enough to lift the wheel once: the reference loses
# the contact at 0.337 ms and regains it at 0.648 ms.
EXCITATION, T = (1.5e-4, 600.0), 0.003


@pytest.fixture(scope="module")
def ref():
    system, sol = study.run_reference(None, EXCITATION, T)
    assert [kind for _, kind in sol.events] == ["loss", "onset"]
    return system, sol


@pytest.mark.parametrize("h,dt", [(1e-5, 2e-7), (1e-6, 2e-8)])
def test_early_return_master_stops_at_the_contact_loss_and_onset(ref, h, dt):
    """The contact FMU returns early at the reference's loss and onset of contact (within dt: the
    coupled system is not the monolithic one; ten times closer at ten times shorter steps); any
    stops between them come at the loss: the contact touching again for an instant, where the
    master hands it the track's rail position at the loss. The errors are those of the same coupling without early
    return, and of master.py's recommended coupling on the FMI 2.0 FMUs."""
    system, sol = ref
    r = master3.run(h, T, "F_mean", "ramp", True, None, EXCITATION)
    (t_loss, _), (t_onset, _) = sol.events
    events = r["events"]
    assert abs(events[0] - t_loss) <= dt and abs(events[-1] - t_onset) <= dt
    assert np.all(np.abs(events[1:-1] - t_loss) <= dt)
    m = study.metrics(r, sol, system)
    m_off = study.metrics(master3.run(h, T, "F_mean", "ramp", False, None, EXCITATION), sol, system)
    m_fmi2 = study.metrics(master.run(h, T, "gauss-seidel", ("vehicle", "contact", "track"), "F_mean", "ramp",
                                      None, EXCITATION), sol, system)
    for k in ("force_error", "mean_force_error", "impulse_error"):
        assert m[k] == pytest.approx(m_off[k], rel=0.05), k
        assert m[k] == pytest.approx(m_fmi2[k], rel=0.05), k
    assert m["force_error"] < 1e3 * h  # 0.55 % of the wheel load at 1e-5 s, 0.007 % at 1e-6 s


def test_without_events_the_fmi3_master_agrees_with_the_fmi2_one(ref):
    """Before the first loss of contact: the two masters differ only in the order of the vehicle
    (contact first here, so that it can stop), which the soft suspension hardly feels. The rail's
    velocity as vC_in (velocity_input) or as der(yC_in) gives the same numbers, bit for bit."""
    h, t_end = 1e-5, 3e-4
    r3 = master3.run(h, t_end, "F_mean", "ramp", True, None, EXCITATION)
    r2 = master.run(h, t_end, "gauss-seidel", ("vehicle", "contact", "track"), "F_mean", "ramp", None, EXCITATION)
    assert len(r3["events"]) == 0
    r3d = master3.run(h, t_end, "F_mean", "derivative", True, None, EXCITATION)  # der(yC_in) for vC_in
    assert np.array_equal(r3["contact.F"], r3d["contact.F"]) and np.array_equal(r3["E_coupling"], r3d["E_coupling"])
    W = ref[0].W
    assert np.max(np.abs(r3["contact.F"] - r2["contact.F"])) < 1e-4 * W
    assert np.max(np.abs(r3["track.z_rail"] - r2["track.z_rail"])) < 1e-10
