"""Identification on rigs it was not tuned on (rigs.py): a fixed handful of the random family,
each fitted from what a bag cut to /joint_states holds, recorded mid-run with its sensors'
noise, encoder counts and latency; and rigs the base does not describe, refused by name with
nothing written. The whole family's figures: bench/identify_family.py and
doc/guide/identification.md."""
import os
import subprocess
import sys

import numpy as np
import pytest

import kane_sim
from kane_sim import identify as ki

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import rigs  # noqa: E402
from conftest import tool  # noqa: E402


# Three regimes of the family, each a different rig (masses and k x[0.5, 2], dampers, friction
# and the rod's inertia drawn), sensors and rate, seeds 100 to 102: measured errors of the
# masses and k 0.055 %, 0.026 % and 2.0 % (the PRBS, whose torque steps between its samples:
# slider 3's mass) at the worst (bench/identify_family.py: the whole family). The
# biased multisine is the long recording's below; the --excite profile is test_identify.py's
# (its rig at seed 103: 0.005 %, 12 s of fitting this suite leaves to the bench).
# The PRBS rig records 60 s: its torque steps between its 200 Hz samples, and on 30 s the fit
# follows a fresh recording 3.004 times the noise off (60 s: 1.9; 120 s: 1.9, measured).
# The servo (seed 104) is test_what_the_energy_windows_cannot_tell_the_output_error_fits's.
@pytest.mark.parametrize("seed, regime, duration", [(100, "oscillation", 30),
                                                    (101, "full_turns", 30), (102, "prbs", 60)])
def test_rigs_of_the_family_are_fitted(seed, regime, duration):
    rig = rigs.draw(seed, regime=regime, duration=duration)
    fit = ki.identify(rigs.record(rig), None, holdout=0)
    assert fit.refusal is None, fit.report()
    assert fit.refined["converged"]
    scores = rigs.score(rig, fit)
    for name in rigs.MASSES + rigs.STIFFNESS:
        row = scores[name]
        if row["told"]:
            # The bound for the worst of a family: 2 %; a servo-held (closed-loop) rig
            # is fitted as recorded, segment by segment.
            assert abs(row["error"]) < 0.025, (name, row, fit.report())
    # Friction the rig has is found, friction it has not comes out near 0: within 40 % of the
    # truth or 3 of its reported sigma.
    for name in rigs.FRICTION:
        row = scores[name]
        if row["told"]:
            assert abs(row["estimate"] - row["truth"]) <= max(0.4 * row["truth"],
                                                              3 * row["sigma"]), (name, row)
    # The bound: a fresh torque within 3 times the noise, checked as a user checks a
    # fit (a fresh recording with the rig's sensors, followed segment by segment); measured 1.0
    # to 1.1 on these four.
    followed = rigs.fresh_recording_error(rig, fit)
    assert max(followed) < 3, (followed, fit.report())
    # The PRBS's torque steps between its 200 Hz samples: the fit names what that alone leaves
    # (slider 4: about 0.2 mm against 18 um of noise); a smooth multisine, or a servo's torque,
    # has no steps and leaves nothing of the kind.
    floor, noise = fit.refined["torque_sampling"], fit.refined["noise"]
    if regime == "prbs":
        assert floor[1] > 3 * noise[1] and "steps between its samples" in fit.report()
    else:
        assert floor == (0.0, 0.0) and "steps between" not in fit.report(), floor


def test_what_the_energy_windows_cannot_tell_the_output_error_fits():
    # A position servo's rig (seed 104: 20 s at 100 Hz): slider 4's friction and a damper act
    # within the energy windows' integration error, and the least squares keeps them at the
    # base's 0. Kept there, slider 4's friction (0.15 N) is -100 % off and a fresh torque
    # re-simulates slider 4 99 times its noise off (measured); the output error fits them.
    rig = rigs.draw(104, regime="servo")
    fit = ki.identify(rigs.record(rig), None, holdout=0)
    assert fit.refusal is None, fit.report()
    assert "friction.slider4_joint" in fit.refined["refit"]
    assert "friction.slider4_joint" not in fit.kept
    assert "fitted by the output error alone" in fit.report()
    for name, row in rigs.score(rig, fit).items():
        if row["truth"]:  # each within 3 of its sigma, and masses and k within 2 %
            assert row["z"] < 3, (name, row, fit.report())
            if name in rigs.MASSES + rigs.STIFFNESS:
                assert abs(row["error"]) < 0.02, (name, row)
    fresh, noise = rigs.fresh_torque_error(rig, fit)
    # The issue's bound: a fresh torque re-simulated within 3 times the sensors' noise, from
    # the truth's states and as a user checks it (a fresh recording followed: 1.1 measured).
    assert fresh[0] < 3 * noise[0] and fresh[1] < 3 * noise[1], (fresh, noise)
    assert max(rigs.fresh_recording_error(rig, fit)) < 3
    # A servo's torque has no steps: no torque-sampling floor.
    assert fit.refined["torque_sampling"] == (0.0, 0.0)


def test_fast_motion_at_a_low_rate_is_fitted_on_shorter_segments():
    # Seed 127: full turns under a biased multisine, 100 Hz sensors, 20 s. The filter's start
    # states of 2 s segments left the output error at 30 times the noise (refused, measured);
    # on 1 s segments it fits the positions to about the noise and the masses within 0.02 %.
    # The whole-recording replay diverges for any parameters here: the fit is judged against the
    # base's parameters through the same segments.
    rig = rigs.draw(127, regime="multisine_bias")
    fit = ki.identify(rigs.record(rig), None, holdout=0)
    assert fit.refusal is None, fit.report()
    assert fit.refined["converged"] and fit.refined["segment_seconds"] == 1.0
    assert "segments of 1 s" in fit.report()
    assert all(fit.refined["position_rms"][k] < fit.refined["base_position_rms"][k]
               for k in (0, 1))
    for name, row in rigs.score(rig, fit).items():
        if row["truth"] and name in rigs.MASSES + rigs.STIFFNESS:
            assert abs(row["error"]) < 0.02 and row["z"] < 3, (name, row, fit.report())


def test_a_long_recording_is_fitted_on_a_bounded_part_with_errors_of_that_part():
    # 200 s at 250 Hz: the least squares sees every sample; the output-error fit 30 of its 99
    # segments, spread over it, one sample in 2 (MAX_SEGMENTS, MAX_ROWS): its time and memory
    # are what a minute's are, an hour's too (bench/identify_scale.py). What it reports is
    # that part's precision: the truth within 3 sigma.
    from kane_sim.identify import refinement
    rig = rigs.draw(7, regime="multisine_bias", duration=200)
    rig.sensors["sensors.rate"] = 250.0
    lines = []
    fit = ki.identify(rigs.record(rig), None, holdout=0, validate=False, progress=lines.append)
    assert fit.refusal is None, fit.report()
    r = fit.refined
    assert (r["segments"], r["segments_of"]) == (refinement.MAX_SEGMENTS, 99)
    assert r["stride"] == 2 and "30 of the recording's 99 spread over it" in fit.report()
    assert r["converged"]
    assert lines[0].startswith("read 50000 samples") and any("iteration 3" in x for x in lines)
    for name, row in rigs.score(rig, fit).items():
        if row["told"] and name in rigs.MASSES + rigs.STIFFNESS:
            assert abs(row["error"]) < 0.01 and row["z"] < 3.5, (name, row)


@pytest.fixture(scope="module")
def lagging_torque(tmp_path_factory):
    """A 12 s PRBS rig whose recorded torque lags the motion by 50 ms (a drive's effort read
    late): no parameters make the model follow it."""
    rig = rigs.draw(102, regime="prbs", duration=12)
    data = rigs.record(rig)
    data["applied_torque"] = np.interp(data["t"] - 0.05, data["t"], data["applied_torque"])
    csv = tmp_path_factory.mktemp("lag") / "rig.csv"
    names = ("t", "q1", "q2", "u1", "u2", "applied_torque")
    np.savetxt(csv, np.column_stack([data[n] for n in names]), delimiter=",",
               header=",".join(names), comments="")
    return csv


def test_a_fit_that_does_not_converge_is_refused_and_written_only_when_forced(lagging_torque,
                                                                              tmp_path):
    # One run, forced: its refusal is said as an unforced one says it, and the file says what it
    # is. (Unforced, a refusal writes nothing and exits 3: test_identify's
    # test_the_cli_refuses_by_pythons_rule_and_says_so_on_stdout, on a refusal that costs no
    # output-error ladder; this one runs every segment length, ~20 s.)
    out = tmp_path / "fitted.yaml"
    args = [tool("identify"), str(lagging_torque), "-o", str(out), "--holdout", "0",
            "--no-validate", "--force"]
    forced = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert forced.returncode == 0, forced.stdout + forced.stderr
    assert "NOT converged" in forced.stdout and "REFUSED" in forced.stdout
    for words in ("more than 3 times their noise", "rod_half_length L and gravity g", "a lag",
                  "--force: writing a refused fit"):
        assert words in forced.stderr, (words, forced.stderr)
    assert "# REFUSED, written with --force: the output-error fit" in out.read_text()
    kane_sim.Config(str(out))  # a config the loader takes


@pytest.mark.parametrize("key, value", [("mechanism.rod_half_length", 0.35),
                                        ("mechanism.gravity", 8.5)])
def test_a_base_that_does_not_describe_the_rig_is_refused_naming_l_and_g(key, value):
    rig = rigs.draw(102, regime="prbs", duration=12)
    base = kane_sim.Config().with_values({key: value})
    # Refused either by the least squares (a mass or inertia far below 0) or by the refinement
    # (the positions not followed): both name L and g, and nothing is written.
    try:
        fit = ki.identify(rigs.record(rig), base, holdout=0, validate=False)
    except ValueError as e:
        assert "not physical" in str(e) and "the base's L and g" in str(e), str(e)
        return
    assert fit.refusal and "rod_half_length L and gravity g" in fit.refusal, fit.report()


@pytest.mark.parametrize("seed", [100, 101, 102, 104, 106, 127])
def test_the_position_noise_is_the_sensors(seed):
    # The output error weighs and judges by the positions' noise, estimated from the data alone
    # (rates.position_noise): within 5 % of the sensors' (their noise and the encoder's counts)
    # on every rig of the family; the derivative filter's residual, used before, was up to 200
    # times it on fast motion. 100 Hz to 1 kHz, encoders of 0, 4096 and 16384 counts.
    from kane_sim.identify.data import load_motion
    from kane_sim.identify.rates import position_noise
    rig = rigs.draw(seed, regime=rigs.REGIMES[(seed - 100) % len(rigs.REGIMES)], duration=20)
    estimate = position_noise(load_motion(rigs.record(rig)))
    truth = rigs.sensor_noise(rig)
    assert np.all(np.abs(estimate / truth - 1) < 0.08), (estimate, truth)


class _Truth:
    """A fit that found the rig's own values: what fresh_recording_error needs of a fit."""

    def __init__(self, rig):
        self.config = rig.config()
        self.names = list(rigs.MASSES + rigs.STIFFNESS + rigs.DAMPERS + rigs.FRICTION)
        self.estimates = {n: self.config[n] for n in self.names}


def test_the_true_model_follows_a_fresh_recording_down_to_its_noise():
    # Seed 102's sensors stamp their readings 4 ms late and slider 4 moves at 0.9 m/s RMS: a row
    # whose t - lag fell before its segment's replay was compared with the replay's first value
    # (3.6 mm off), and the true parameters followed the fresh recording to 6.4 times slider 4's
    # noise (measured). Each replay now starts REPLAY_MARGIN before its rows: 1.0.
    rig = rigs.draw(102, regime="prbs")
    ratio = rigs.fresh_recording_error(rig, _Truth(rig))
    assert max(ratio) < 1.3, ratio


def test_a_torque_later_than_the_lag_may_be_is_refused_naming_it():
    # The effort read 50 ms late, sensors as noisy as sensors.yaml's: the fit reaches 2.3 times
    # the noise with the lag at its -25 ms bound and masses 8-14 % off (measured by a fresh-eye
    # user before this refusal; written then, with exit 0).
    rig = rigs.draw(100, regime="oscillation", duration=12)
    rig.sensors.update({"sensors.crank_position_noise": 0.002,
                        "sensors.slider4_position_noise": 0.0005})
    data = rigs.record(rig)
    data["applied_torque"] = np.interp(data["t"] - 0.05, data["t"], data["applied_torque"])
    fit = ki.identify(data, None, holdout=0, validate=False)
    assert fit.refined["converged"]
    assert fit.refusal and "ran into the fit's bound (-25 ms" in fit.refusal, fit.refusal
