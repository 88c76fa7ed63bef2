"""The gpsemu Python module: configured with the CLI's keys, deterministic, and byte-identical
with the CLI (`gpsemu --fast --output stdout`) for the same seed, settings and start time."""
import math
import os
import select
import subprocess

import numpy as np
import pytest

import gpsemu

START = "2024-05-01T12:00:00Z"
KEYS = {"noise": "cgrw", "width": 1.0, "seed": 7, "rate": 10, "origin": "43.07,-89.41,260",
        "start-time": START}


def cli_nmea(keys, epochs):
    """The CLI's NMEA for `keys` over `epochs` epochs (stdout, --fast)."""
    binary = os.environ.get("GPSEMU_BINARY")
    if not binary:
        pytest.skip("GPSEMU_BINARY not set (run through CTest)")
    args = [binary, "--fast", "--output", "stdout", "--log-level", "off",
            "--duration", repr(epochs / float(keys.get("rate", 1)))]
    for key, value in keys.items():
        args += ["--" + key, value if isinstance(value, str) else repr(value)]
    return subprocess.run(args, check=True, capture_output=True, timeout=60).stdout


def test_import_and_version():
    assert gpsemu.__version__.count(".") == 2
    assert {"rate", "origin", "noise", "width", "seed", "start-time"} <= set(gpsemu.option_names())


@pytest.mark.parametrize("extra", [
    {},
    {"noise": "chrono", "chrono": "0,0.047,100,0.016,0.152"},
    {"noise": "gaussian", "gaussian-sigma": "1,1,2"},
    {"noise": "gauss-markov", "gm-sigma": 0.8, "gm-tau": 30},
    {"noise": "none", "rate": 1, "sentences": "RMC,VTG,GGA,GSA,GSV,GLL,GST,ZDA"},
    {"fix-quality": "rtk-fixed", "cold-start": "3,2"},
])
def test_step_is_the_cli_output(extra):
    keys = {**KEYS, **extra}
    missing = set(keys) - set(gpsemu.option_names())
    if missing:
        pytest.skip(f"keys not in this build: {sorted(missing)}")
    epochs = 100
    expected = cli_nmea(keys, epochs)
    assert expected.count(b"GGA") == epochs
    assert gpsemu.Receiver(keys).run(epochs) == expected
    # The same truth given by the caller (sim:stationary is the origin, at rest).
    rx = gpsemu.Receiver(keys)
    assert b"".join(rx.step_enu((0.0, 0.0, 0.0)).nmea for _ in range(epochs)) == expected
    track = gpsemu.Receiver(keys).track(np.zeros((epochs, 3)))
    assert track["nmea"] == expected


def test_moving_scenario_is_the_cli_output():
    keys = {**KEYS, "source": "sim:circle", "seed": 3}
    assert gpsemu.Receiver(keys).run(50) == cli_nmea(keys, 50)


def test_keyword_arguments_use_underscores_for_dashes():
    a = gpsemu.Receiver(KEYS).run(5)
    b = gpsemu.Receiver(noise="cgrw", width=1.0, seed=7, rate=10, origin=(43.07, -89.41, 260),
                        start_time=START).run(5)
    assert a == b
    # numpy scalars are numbers too
    c = gpsemu.Receiver(noise="cgrw", width=np.float64(1.0), seed=np.int64(7), rate=np.int32(10),
                        origin=np.array([43.07, -89.41, 260.0]).tolist(), start_time=START).run(5)
    assert c == a


def test_epoch_times_follow_the_grid():
    rx = gpsemu.Receiver(KEYS)
    first = rx.next_epoch_ns
    assert first == 1714564800 * 10**9
    times = [rx.step().time_ns for _ in range(3)]
    assert times == [first, first + 10**8, first + 2 * 10**8]
    assert rx.rate_hz == 10.0


def test_noise_is_seeded_and_deterministic():
    a = gpsemu.generate(600, 10, KEYS)
    b = gpsemu.Noise(KEYS).generate(600, 10)
    assert a.shape == (600, 3) and a.dtype == np.float64
    assert np.array_equal(a, b)
    assert not np.array_equal(a, gpsemu.generate(600, 10, {**KEYS, "seed": 8}))
    # Successive calls continue the same process.
    n = gpsemu.Noise(KEYS)
    assert np.array_equal(np.vstack([n.generate(200, 10), n.generate(400, 10)]), a)
    assert np.ptp(a[:, 0]) > 0.0


def test_composite_model_with_the_cli_keys():
    smooth = {"noise": "gauss-markov", "gm-order": "2", "gm-sigma": "0.5", "gm-tau": "20", "seed": 3}
    keys = {"noise": "composite", "composite-sigma": "0.5", "composite-tau": "20", "seed": 3}
    # No jitter, no jumps: exactly its smooth part alone (same streams under the seed).
    assert np.array_equal(gpsemu.generate(300, 5, keys), gpsemu.generate(300, 5, smooth))
    jumpy = {**keys, "composite-jitter": "0.05", "composite-jump-rate": "0.05", "composite-jump-size": "0.5",
             "composite-jump-decay": "30"}
    a = gpsemu.generate(300, 5, jumpy)
    assert np.array_equal(a, gpsemu.generate(300, 5, jumpy))
    assert not np.array_equal(a, gpsemu.generate(300, 5, keys))
    with pytest.raises(gpsemu.Error, match="composite-jitter"):
        gpsemu.Noise({**keys, "composite-jitter": "-1"})


def test_receiver_position_is_truth_plus_noise():
    noise = gpsemu.generate(50, 10, KEYS)
    rx = gpsemu.Receiver(KEYS)
    truth = np.column_stack([np.arange(50) * 0.5, np.zeros(50), np.full(50, 2.0)])
    out = rx.track(truth, np.tile([5.0, 0.0, 0.0], (50, 1)))
    assert out["enu"].shape == (50, 3) and out["lla"].shape == (50, 3)
    np.testing.assert_allclose(out["enu"] - truth, noise, atol=1e-6)
    assert out["nmea"].count(b"GGA,") == 50  # talker GN: the default receiver tracks several systems


# The truth's velocity passed through: the velocity's own error off.
EXACT_VELOCITY = {"velocity-noise": 0, "velocity-wander": 0}


def test_geodetic_truth_equals_enu_truth():
    keys = {**KEYS, **EXACT_VELOCITY}
    a, b = gpsemu.Receiver(keys), gpsemu.Receiver(keys)
    lat, lon, alt = a.origin
    assert (lat, lon, alt) == (43.07, -89.41, 260.0)
    g = a.to_geodetic(10.0, -5.0, 1.0)
    np.testing.assert_allclose(a.to_enu(*g), (10.0, -5.0, 1.0), atol=1e-6)
    for _ in range(5):
        ea = a.step_geodetic(*g, velocity=(1.0, 0.0, 0.0))
        eb = b.step_enu((10.0, -5.0, 1.0), (1.0, 0.0, 0.0))
        assert ea.nmea == eb.nmea
        assert ea.has_fix and abs(ea.speed_mps - 1.0) < 1e-9


def test_vertical_velocity_is_reported():
    rx = gpsemu.Receiver({**KEYS, **EXACT_VELOCITY})
    e = rx.step_enu((0.0, 0.0, 0.0), (1.0, 0.0, 2.5))
    assert e.has_fix and abs(e.vel_up_mps - 2.5) < 1e-9 and abs(e.speed_mps - 1.0) < 1e-9
    # With its error (the default) the velocity is the truth's within a few of its sigmas, not exact.
    noisy = gpsemu.Receiver(KEYS).step_enu((0.0, 0.0, 0.0), (1.0, 0.0, 2.5))
    assert abs(noisy.speed_mps - 1.0) < 0.3 and noisy.speed_mps != 1.0
    assert abs(noisy.vel_up_mps - 2.5) < 0.5 and noisy.vel_up_mps != 2.5


def test_no_truth_is_no_fix():
    rx = gpsemu.Receiver({**KEYS, "sentences": "RMC,GGA"})
    e = rx.step_no_fix()
    assert not e.has_fix
    assert all(math.isnan(x) for x in e.position + e.position_enu)
    assert b",V," in e.nmea.split(b"\r\n")[0]
    assert rx.step_enu((0, 0, 0)).has_fix


def test_bad_keys_and_values_name_the_key():
    with pytest.raises(gpsemu.Error, match="widht"):
        gpsemu.Receiver({"widht": 2})
    with pytest.raises(ValueError, match="rate"):
        gpsemu.Receiver(rate=0)
    with pytest.raises(gpsemu.Error, match="pink"):
        gpsemu.Noise(noise="pink")
    with pytest.raises(gpsemu.Error, match="sim:"):
        gpsemu.Receiver(source="udp:5000").step()


def test_config_file_keys(tmp_path):
    toml = tmp_path / "rx.toml"
    toml.write_text('rate = 10\nseed = 7\nwidth = 1.0\norigin = "43.07,-89.41,260"\n')
    a = gpsemu.Receiver({"start-time": START}, config_file=toml).run(10)
    assert a == gpsemu.Receiver(KEYS).run(10)


def test_epoch_bytes_through_a_pty():
    """The README loop: the receiver's bytes written to a pseudo-terminal a client reads."""
    master, slave = os.openpty()
    try:
        import tty
        tty.setraw(slave)
        epoch = gpsemu.Receiver(KEYS).step_enu((0, 0, 0)).nmea
        os.write(master, epoch)
        got = b""
        while len(got) < len(epoch):
            ready, _, _ = select.select([slave], [], [], 5.0)
            assert ready, "pty read timed out"
            got += os.read(slave, 4096)
        assert got == epoch
    finally:
        os.close(master)
        os.close(slave)


def test_receiver_fault_calls_apply_from_the_next_step():
    rx = gpsemu.Receiver(KEYS)
    assert rx.step().has_fix
    answer = rx.fault("outage", duration=0.2)         # 2 epochs at 10 Hz
    assert answer["class"] == "FAULT" and answer["starts"] == "next epoch"
    assert [rx.step().has_fix for _ in range(3)] == [False, False, True]
    rx.control({"fault": "outage"})
    assert not rx.step().has_fix
    assert rx.status()["receivers"][0]["faults"][0]["fault"] == "outage"
    assert rx.clear("outage")["cleared"] == 1
    assert rx.step().has_fix
    assert rx.status()["receivers"][0]["epochs"] == 6
    bad = rx.fault("jam", db=99)
    assert bad["class"] == "ERROR" and "db" in bad["message"]


def test_control_reaches_a_running_gpsemu_over_tcp(tmp_path):
    binary = os.environ.get("GPSEMU_BINARY")
    if not binary:
        pytest.fail("GPSEMU_BINARY not set (run through CTest)")
    proc = subprocess.Popen([binary, "--rate", "10", "--duration", "20", "--output", "file:" + str(tmp_path / "o.nmea"),
                             "--control", "tcp:127.0.0.1:0", "--log-level", "info"], stderr=subprocess.PIPE)
    try:
        spec, text = None, b""
        while spec is None:
            ready, _, _ = select.select([proc.stderr], [], [], 10.0)
            assert ready, "gpsemu did not open its control socket: " + text.decode()
            chunk = os.read(proc.stderr.fileno(), 4096)
            assert chunk, "gpsemu exited: " + text.decode()
            text += chunk
            for line in text.decode().splitlines():
                if "control socket tcp:" in line:
                    spec = "tcp:" + line.split("control socket tcp:")[1].split(":")[0] + ":" + \
                           line.split("control socket tcp:")[1].split(":")[1]
        ctl = gpsemu.Control(spec)
        assert ctl.fault("garble", rate=0.25, receiver=0)["class"] == "FAULT"
        faults = ctl.status()["receivers"][0]["faults"]
        assert [f["fault"] for f in faults] == ["garble"]   # pending until the next epoch takes it, then active
        assert ctl.clear("all")["class"] == "CLEAR"
        assert ctl.send('{"nonsense":1}')["class"] == "ERROR"
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    with pytest.raises(gpsemu.Error):
        gpsemu.Control(spec, timeout_s=1).status()
