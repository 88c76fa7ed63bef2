#!/usr/bin/env python3
"""The real driver as the judge (docs/autopilots.md): PX4-GPSDrivers' own u-blox and NMEA drivers,
built from a checkout the user points at, read gpsemu over a pty, and what they publish is checked
against the truth gpsemu was fed and the fix it reported.

  tools/driver-check px4 --px4-gpsdrivers DIR [--boots N] [--seconds S] [--quick] [--only TEXT]

Builds tools/driver-check/px4_harness.cpp around DIR's src/ubx.cpp, nmea.cpp, gps_helper.cpp,
rtcm.cpp, unicore.cpp and crc.cpp (our own definitions.h stands in for PX4's, found first), then
runs the matrix: each u-blox model x start state (factory, --protocol ubx, nmea+ubx) x --rate 1, 5,
10, each boot a fresh gpsemu whose pty the driver opens at a random phase; the faults (jam, spoof,
outage) on each model; RTK float/fixed with RTCM3 written through the driver's injection path;
the heading of a moving-base rover; PX4's NMEA driver on the default sentences (and with GST).
Prints the table and exits 1 when any check failed, 2 on bad usage, 77 when no checkout was given
(GPSEMU_PX4_GPSDRIVERS unset: CTest reports the test as skipped, never as passed).
"""
import argparse
import json
import math
import os
import random
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import tty

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SKIP = 77
DRIVER_SOURCES = ["ubx.cpp", "nmea.cpp", "gps_helper.cpp", "rtcm.cpp", "unicore.cpp", "crc.cpp"]
# PX4's GPSDriverUBX::Board of each model; `generic` answers as a u-blox 8 (with --protocol: it has
# no factory state of a u-blox, it is an NMEA receiver); the M10 (MON-VER hwVersion 000A0000) is
# Board::u_blox10 = 11.
MODELS = {"ublox-m8n": 8, "ublox-m9n": 9, "ublox-f9p": 10, "ublox-m10": 11, "generic": 8}
# PX4's solution period with GPS_UBX_RATE 0: the legacy path's CFG-RATE 200 ms on an M8, 125 ms on
# a u-blox 9 (M9N), 200 ms on an F9P, the default 100 ms on an M10 (ubx.cpp configureDevice()).
DRIVER_PERIOD_S = {"ublox-m8n": 0.2, "ublox-m9n": 0.125, "ublox-f9p": 0.2, "ublox-m10": 0.1, "generic": 0.2}
ORIGIN = (43.0725, -89.4125, 260.0)
SIGMA = (0.6, 0.8, 1.2)  # gaussian noise east, north, up (m): hAcc 1.0, vAcc 1.2, above the floors
VEL = (3.0, 4.0, 1.0)  # the truth's velocity east, north, up (m/s): a climb, so velD is checked
# gpsemu's default velocity error, 1 sigma a horizontal axis and vertical (m/s): sqrt(0.03^2 + 0.02^2), x 1.6 up
VSIGMA = (math.hypot(0.03, 0.02), 1.6 * math.hypot(0.03, 0.02))
YAW_DEG = 30.0


# ---------------------------------------------------------------- building the harness

def build_harness(gpsdrivers, build_dir):
    src = os.path.join(gpsdrivers, "src")
    missing = [f for f in DRIVER_SOURCES + ["ubx.h", "gps_helper.h"] if not os.path.exists(os.path.join(src, f))]
    if missing:
        sys.exit(f"driver-check: {gpsdrivers} is not a PX4-GPSDrivers checkout (no src/{missing[0]})")
    os.makedirs(build_dir, exist_ok=True)
    include = os.path.join(HERE, "px4_include")
    common = ["-I" + include, "-I" + src, '-DGPS_DEFINITIONS_HEADER="definitions.h"', "-O1", "-g"]
    objects = []
    jobs = []
    for f in DRIVER_SOURCES + ["px4_harness.cpp"]:
        path = os.path.join(HERE, f) if f == "px4_harness.cpp" else os.path.join(src, f)
        obj = os.path.join(build_dir, f.replace(".cpp", ".o"))
        objects.append(obj)
        deps = [path, os.path.join(include, "definitions.h")]
        if os.path.exists(obj) and all(os.path.getmtime(obj) >= os.path.getmtime(d) for d in deps):
            continue
        # Their code with their own standard and no warnings of ours; ours with the project's flags.
        flags = ["-std=c++20", "-Wall", "-Wextra", "-Werror"] if f == "px4_harness.cpp" else ["-std=c++17", "-w"]
        jobs.append(["g++", *flags, *common, "-c", path, "-o", obj])
    for cmd in jobs:
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("driver-check: building the harness failed:\n" + " ".join(cmd) + "\n" + r.stderr)
    exe = os.path.join(build_dir, "px4-harness")
    if jobs or not os.path.exists(exe):
        r = subprocess.run(["g++", "-o", exe, *objects], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("driver-check: linking the harness failed:\n" + r.stderr)
    return exe


def gpsdrivers_commit(gpsdrivers):
    r = subprocess.run(["git", "-C", gpsdrivers, "rev-parse", "HEAD"], capture_output=True, text=True)
    if r.returncode == 0:
        return r.stdout.strip()
    marker = os.path.join(gpsdrivers, ".commit")
    return open(marker).read().strip() if os.path.exists(marker) else "unknown"


# ---------------------------------------------------------------- the world around the driver

def free_udp_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


class PoseSender(threading.Thread):
    """The truth: a climbing straight line from the origin at VEL, sent as JSON poses at 20 Hz."""

    def __init__(self, ports, t0):
        super().__init__(daemon=True)
        self.ports, self.t0, self.stop = ports, t0, threading.Event()
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

    def run(self):
        while not self.stop.is_set():
            now = time.time()
            x, y, z = truth_enu(now, self.t0)
            pose = json.dumps({"t": now, "x": x, "y": y, "z": z, "ve": VEL[0], "vn": VEL[1], "vu": VEL[2],
                               "yaw_deg": YAW_DEG}).encode()
            for port in self.ports:
                self.sock.sendto(pose, ("127.0.0.1", port))
            self.stop.wait(0.05)


def truth_enu(t, t0):
    dt = t - t0
    return VEL[0] * dt, VEL[1] * dt, VEL[2] * dt


def enu_error(rec, t0):
    """The driver's position minus the truth at the fix's UTC time, metres east, north, up."""
    t = rec["time_utc_usec"] / 1e6
    x, y, z = truth_enu(t, t0)
    a, e2 = 6378137.0, 6.69437999014e-3
    lat0 = math.radians(ORIGIN[0])
    s = math.sin(lat0)
    n_radius = a / math.sqrt(1 - e2 * s * s)
    m_radius = a * (1 - e2) / (1 - e2 * s * s) ** 1.5
    de = math.radians(rec["lon"] - ORIGIN[1]) * n_radius * math.cos(lat0) - x
    dn = math.radians(rec["lat"] - ORIGIN[0]) * m_radius - y
    du = rec["alt_msl"] - ORIGIN[2] - z
    return de, dn, du


class Control:
    def __init__(self, path):
        for _ in range(50):
            if os.path.exists(path):
                break
            time.sleep(0.05)
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.sock.connect(path)
        self.file = self.sock.makefile("rw")

    def send(self, request):
        self.file.write(json.dumps(request) + "\n")
        self.file.flush()
        return json.loads(self.file.readline())


def rtcm3_frame(payload_bits):
    """An RTCM3 frame around a payload given as a bit string (our own encoder: 0xD3, length, CRC-24Q)."""
    payload_bits += "0" * (-len(payload_bits) % 8)
    payload = int(payload_bits, 2).to_bytes(len(payload_bits) // 8, "big") if payload_bits else b""
    body = bytes([0xD3, (len(payload) >> 8) & 0x03, len(payload) & 0xFF]) + payload
    crc = 0
    for byte in body:
        crc ^= byte << 16
        for _ in range(8):
            crc <<= 1
            if crc & 0x1000000:
                crc ^= 0x1864CFB
    return body + (crc & 0xFFFFFF).to_bytes(3, "big")


def bits(value, width):
    return format(value & ((1 << width) - 1), "0%db" % width)


def rtcm_base_epoch(station, tow_ms):
    """A static base's epoch: 1005 (its antenna at the origin, ECEF) and a GPS MSM4 (1074) of one
    satellite and one signal. gpsemu uses the message types, the base position and the MSM's masks
    and length (docs/rtk.md); the observation values are not used."""
    lat, lon, h = math.radians(ORIGIN[0]), math.radians(ORIGIN[1]), ORIGIN[2] - 34.7
    a, e2 = 6378137.0, 6.69437999014e-3
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    ecef = ((n + h) * math.cos(lat) * math.cos(lon), (n + h) * math.cos(lat) * math.sin(lon),
            (n * (1 - e2) + h) * math.sin(lat))
    m1005 = (bits(1005, 12) + bits(station, 12) + bits(0, 6) + "1" + "0" + "0" + "0" +
             bits(round(ecef[0] * 1e4), 38) + "0" + "0" + bits(round(ecef[1] * 1e4), 38) + bits(0, 2) +
             bits(round(ecef[2] * 1e4), 38))
    sat_mask = "1" + "0" * 63
    sig_mask = "1" + "0" * 31
    header = (bits(1074, 12) + bits(station, 12) + bits(tow_ms, 30) + "0" + bits(0, 3) + bits(0, 7) +
              bits(0, 2) + bits(0, 2) + "0" + bits(0, 3) + sat_mask + sig_mask + "1")
    sat_data = bits(75, 8) + bits(0, 10)
    sig_data = bits(0, 15) + bits(0, 22) + bits(0, 4) + "0" + bits(45, 6)
    return rtcm3_frame(m1005) + rtcm3_frame(header + sat_data + sig_data)


def rtcm_frames(buf):
    """Whole RTCM3 frames out of a byte stream (the moving base's output); the rest is kept."""
    frames = []
    while True:
        i = buf.find(b"\xd3")
        if i < 0:
            return frames, b""
        buf = buf[i:]
        if len(buf) < 3:
            return frames, buf
        length = ((buf[1] & 0x03) << 8) | buf[2]
        if buf[1] & 0xFC:
            buf = buf[1:]
            continue
        if len(buf) < length + 6:
            return frames, buf
        frame = buf[:length + 6]
        if rtcm3_frame_check(frame):
            frames.append(frame)
            buf = buf[length + 6:]
        else:
            buf = buf[1:]


def rtcm3_frame_check(frame):
    crc = 0
    for byte in frame[:-3]:
        crc ^= byte << 16
        for _ in range(8):
            crc <<= 1
            if crc & 0x1000000:
                crc ^= 0x1864CFB
    return (crc & 0xFFFFFF) == int.from_bytes(frame[-3:], "big")


# ---------------------------------------------------------------- one run

class Run:
    """One gpsemu and one driver over its pty; `events` is what the harness printed."""

    def __init__(self, ctx, name, emu_args, harness_args, seconds, fleet_config=None, pose_ports=1,
                 rover_link="gps", base_link=None):
        self.ctx, self.name, self.seconds = ctx, name, seconds
        self.dir = tempfile.mkdtemp(prefix="drvchk_", dir=ctx.tmp)
        self.ports = [free_udp_port() for _ in range(pose_ports)]
        self.ctl_path = os.path.join(self.dir, "ctl")
        self.device = os.path.join(self.dir, rover_link)
        self.base = os.path.join(self.dir, base_link) if base_link else None
        args = [ctx.gpsemu, "--log-level", "info", "--control", "unix:" + self.ctl_path,
                "--origin", "%.6f,%.6f,%.1f" % ORIGIN]
        if fleet_config is not None:
            cfg = os.path.join(self.dir, "fleet.toml")
            with open(cfg, "w") as f:
                f.write(fleet_config.format(dir=self.dir, port0=self.ports[0], port1=self.ports[-1]))
            args += ["--config", cfg]
        else:
            args += ["--source", "udp:127.0.0.1:%d" % self.ports[0], "--output", "pty:" + self.device]
        self.emu_args = args + emu_args
        self.harness_args = harness_args
        self.events, self.stdin_feed = [], None

    def start(self):
        self.t0 = time.time()
        self.emu_log = open(os.path.join(self.dir, "gpsemu.log"), "w")
        self.emu = subprocess.Popen(self.emu_args, stdout=self.emu_log, stderr=subprocess.STDOUT)
        self.poses = PoseSender(self.ports, self.t0)
        self.poses.start()
        for _ in range(100):
            if os.path.exists(self.device) or self.emu.poll() is not None:
                break
            time.sleep(0.02)
        if self.emu.poll() is not None:
            raise RuntimeError("gpsemu exited at start: " + open(os.path.join(self.dir, "gpsemu.log")).read())
        self.control = Control(self.ctl_path)
        time.sleep(self.ctx.rng.uniform(0.3, 1.3))  # the driver opens the port at a random phase
        self.trace = os.path.join(self.dir, "trace.txt")
        self.harness = subprocess.Popen(
            [self.ctx.harness, "--device", self.device, "--seconds", str(self.seconds), "--trace", self.trace,
             *self.harness_args],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=open(os.path.join(self.dir, "harness.log"), "w"),
            text=False)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.harness.stdout:
            try:
                ev = json.loads(line)
            except ValueError:
                continue
            self.events.append(ev)

    def inject(self, data):
        try:
            self.harness.stdin.write(data)
            self.harness.stdin.flush()
        except (BrokenPipeError, ValueError):
            pass

    def configured_at(self, timeout=8.0):
        end = time.time() + timeout
        while time.time() < end:
            for ev in list(self.events):
                if ev["ev"] == "configure" and ev["ret"] == 0:
                    return ev["wall"]
            time.sleep(0.02)
        return None

    def finish(self):
        self.harness.wait(timeout=self.seconds + 30)
        self.reader.join(timeout=5)
        try:
            self.status = self.control.send({"status": True})
        except OSError:
            self.status = None
        self.emu.terminate()
        try:
            self.emu.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.emu.kill()
        self.poses.stop.set()
        self.emu_log.close()

    def of(self, kind):
        return [e for e in self.events if e["ev"] == kind]

    def keep(self, failed):
        if failed and self.ctx.keep:
            dest = os.path.join(self.ctx.keep, self.name.replace(" ", "_").replace("/", "-"))
            shutil.rmtree(dest, ignore_errors=True)
            shutil.copytree(self.dir, dest, ignore=lambda d, names: [n for n in names if n in ("gps", "base", "ctl")])
        shutil.rmtree(self.dir, ignore_errors=True)


# ---------------------------------------------------------------- the checks

class Checks:
    def __init__(self):
        self.failures = []

    def check(self, ok, what):
        if not ok:
            self.failures.append(what)
        return ok


def common_checks(run, c, driver_period, expect_board=None):
    conf = run.of("configure")
    c.check(len(conf) >= 1 and conf[0]["ret"] == 0, "configure() failed the first time (%s)" %
            ", ".join(str(e["ret"]) for e in conf))
    c.check(len(conf) <= 1, "%d configure() calls (the driver restarted)" % len(conf))
    if expect_board is not None and conf:
        c.check(conf[0]["board"] == expect_board, "board %s, expected %d" % (conf[0]["board"], expect_board))
    c.check(not run.of("timeout"), "%d receive timeouts" % len(run.of("timeout")))
    gps = run.of("gps")
    if conf and conf[0]["ret"] == 0:
        span = run.seconds - conf[0]["ms"] / 1000 - 1.0
        c.check(len(gps) >= 0.8 * span / driver_period, "%d sensor_gps in %.1f s at %.3f s a solution" %
                (len(gps), span, driver_period))
    return gps


def position_checks(run, c, gps, skip_s=1.0, vertical_velocity=True, sigma_scale=1.0):
    """Fix, position against the truth within 4 eph / 4 epv, velocity, time, eph/epv."""
    stats = {"pos": 0.0, "alt": 0.0, "vel": 0.0, "veld": 0.0, "eph": [], "epv": []}
    first = gps[0]["wall"] if gps else 0
    prev = None
    for g in gps:
        if g["wall"] - first < skip_s:
            continue
        if not c.check(g["fix"] >= 3, "fix type %d at %.1f s" % (g["fix"], g["wall"] - run.t0)):
            break
        de, dn, du = enu_error(g, run.t0)
        h = math.hypot(de, dn)
        stats["pos"], stats["alt"] = max(stats["pos"], h), max(stats["alt"], abs(du))
        stats["eph"].append(g["eph"])
        stats["epv"].append(g["epv"])
        if g["eph"] > 0:
            stats.setdefault("ratio", []).append(h / g["eph"])
        # The error about the truth is the noise model's (sigma per axis, scaled by the fix quality).
        k = sigma_scale * 5
        c.check(abs(de) <= k * SIGMA[0] + 0.05 and abs(dn) <= k * SIGMA[1] + 0.05,
                "horizontal error %.2f m east %.2f m north, beyond 5 sigma" % (de, dn))
        c.check(abs(du) <= k * SIGMA[2] + 0.15, "vertical error %.2f m, beyond 5 sigma" % du)
        # The velocity has its own error (gpsemu's default: VSIGMA an axis): within 5 sigma of the truth.
        dv = math.hypot(g["vel_e"] - VEL[0], g["vel_n"] - VEL[1])
        stats["vel"] = max(stats["vel"], dv)
        c.check(dv <= 5 * VSIGMA[0], "horizontal velocity off by %.3f m/s, beyond 5 sigma" % dv)
        c.check(abs(g["vel"] - math.hypot(VEL[0], VEL[1])) <= 5 * VSIGMA[0], "ground speed %.3f m/s" % g["vel"])
        cog_err = abs((g["cog"] - math.atan2(VEL[0], VEL[1]) + math.pi) % (2 * math.pi) - math.pi)
        c.check(cog_err <= math.atan2(5 * VSIGMA[0], math.hypot(VEL[0], VEL[1])),
                "course over ground %.2f deg, truth %.2f" %
                (math.degrees(g["cog"]), math.degrees(math.atan2(VEL[0], VEL[1]))))
        c.check(g["vel_ned_valid"] == 1, "vel_ned_valid 0 with a 3-D fix")
        if vertical_velocity:  # u-blox: sAcc, and the vertical velocity NMEA does not have
            c.check(g["s_var"] > 0, "s_variance_m_s 0 (NAV-PVT sAcc)")
            stats["veld"] = max(stats["veld"], abs(g["vel_d"] + VEL[2]))
            c.check(abs(g["vel_d"] + VEL[2]) <= 5 * VSIGMA[1], "vel_d %.3f m/s, truth %.3f" % (g["vel_d"], -VEL[2]))
        late = g["wall"] - g["time_utc_usec"] / 1e6
        c.check(0 <= late <= 0.6, "sensor_gps %.3f s after its fix time" % late)
        if prev is not None:
            c.check(g["time_utc_usec"] > prev["time_utc_usec"], "fix time went back")
        prev = g
    c.check(prev is not None, "no sensor_gps with a fix")
    return stats


def wire_from_receiver(run):
    """The bytes the receiver sent, from the harness's wire trace."""
    data = bytearray()
    with open(run.trace) as f:
        for line in f:
            if line.startswith("<"):
                data += bytes.fromhex(line.split()[2])
    return bytes(data)


def nav_pvt_by_time(run):
    """NAV-PVT frames on the wire by the fix time the driver derives from them (UTC microseconds)."""
    import calendar
    import struct
    data, out, i = wire_from_receiver(run), {}, 0
    while True:
        i = data.find(b"\xb5\x62\x01\x07", i)
        if i < 0 or i + 6 + 92 > len(data):
            return out
        length = data[i + 4] | (data[i + 5] << 8)
        p = data[i + 6:i + 6 + length]
        i += 6 + length
        if length != 92 or len(p) != 92:
            continue
        year, month, day, hour, minute, sec = struct.unpack_from("<HBBBBB", p, 4)
        nano = struct.unpack_from("<i", p, 16)[0]
        h_acc, v_acc = struct.unpack_from("<II", p, 40)
        try:
            epoch = calendar.timegm((year, month, day, hour, minute, sec, 0, 0, 0))
        except (ValueError, OverflowError):
            continue
        us = epoch * 1000000 + int(nano / 1000)
        out[us] = {"hAcc": h_acc, "vAcc": v_acc, "numSV": p[23], "fixType": p[20], "flags": p[21]}


def gst_sigmas(run):
    """(sigma lat, sigma lon, sigma alt) of each GST on the wire, in order."""
    text = wire_from_receiver(run).decode("ascii", "replace")
    out = []
    for line in text.split("\n"):
        if line[3:7] == "GST," and "*" in line:
            f = line.split("*")[0].split(",")
            try:
                out.append((float(f[6]), float(f[7]), float(f[8])))
            except (ValueError, IndexError):
                pass
    return out


def accuracy_checks(run, c, gps):
    """eph/epv are the hAcc/vAcc of the NAV-PVT the driver read (the same fix time, on the wire)."""
    pvts = nav_pvt_by_time(run)
    matched = 0
    for g in gps:
        pvt = pvts.get(g["time_utc_usec"])
        if pvt is None or g["fix"] < 3:
            continue
        matched += 1
        c.check(abs(g["eph"] - pvt["hAcc"] / 1000) <= 0.0015 and abs(g["epv"] - pvt["vAcc"] / 1000) <= 0.0015,
                "eph/epv %.3f/%.3f, NAV-PVT hAcc/vAcc %.3f/%.3f" % (g["eph"], g["epv"], pvt["hAcc"] / 1000,
                                                                     pvt["vAcc"] / 1000))
        c.check(g["sats"] == pvt["numSV"], "satellites_used %d, NAV-PVT numSV %d" % (g["sats"], pvt["numSV"]))
    c.check(matched >= 0.8 * len([g for g in gps if g["fix"] >= 3]),
            "%d of %d sensor_gps matched a NAV-PVT on the wire" % (matched, len(gps)))
    return matched


def median(xs):
    return sorted(xs)[len(xs) // 2] if xs else float("nan")


def p95(xs):
    return sorted(xs)[int(0.95 * (len(xs) - 1))] if xs else float("nan")


def fmt_max(x):
    return "%.2f" % x


# ---------------------------------------------------------------- the cases

def matrix_case(ctx, model, state, rate, boot, ubx_rate=0):
    """`ubx_rate`: PX4's GPS_UBX_RATE (0: the driver's choice per model)."""
    label = state if not ubx_rate else "%s, GPS_UBX_RATE %d" % (state, ubx_rate)
    name = "%s %s %dHz #%d" % (model, label, rate, boot)
    emu = ["--receiver", model, "--rate", str(rate), "--noise", "gaussian",
           "--gaussian-sigma", "%g,%g,%g" % SIGMA, "--seed", str(ctx.rng.randrange(1, 10 ** 6))]
    if state != "factory":
        emu += ["--protocol", state]
    harness = ["--driver", "ubx"] + (["--ubx-rate", str(ubx_rate)] if ubx_rate else [])
    run = Run(ctx, name, emu, harness, ctx.seconds)
    run.start()
    run.finish()
    c = Checks()
    # The M8's CFG-RATE path ignores GPS_UBX_RATE (200 ms); the VALSET path takes it.
    period = 1.0 / ubx_rate if ubx_rate and MODELS[model] != 8 else DRIVER_PERIOD_S[model]
    gps = common_checks(run, c, period, MODELS[model])
    st = position_checks(run, c, gps)
    accuracy_checks(run, c, gps)
    if st["eph"]:
        st["eph_med"], st["epv_med"] = median(st["eph"]), median(st["epv"])
    # Satellites: numSV against gpsemu's own count, satellite_info's used flags against numSV.
    if gps and run.status:
        used = run.status["receivers"][0].get("satellites_used")
        c.check(gps[-1]["sats"] == used, "satellites_used %d, gpsemu used %s" % (gps[-1]["sats"], used))
    sats = run.of("sat")
    c.check(len(sats) > 0, "no satellite_info")
    for s in sats[1:]:
        c.check(s["count"] > 0 and s["used"] >= 4, "satellite_info count %d used %d" % (s["count"], s["used"]))
    # The RF state without a fault: MON-RF (u-blox 9) or MON-HW (M8).
    for g in gps[2:]:
        c.check(g["noise"] == 89 and g["jam_ind"] == 9, "noise %d jamInd %d without a jam" % (g["noise"], g["jam_ind"]))
        if MODELS[model] != 8:
            c.check(g["jam_state"] == 1, "jamming_state %d without a jam" % g["jam_state"])
        break
    conf = run.of("configure")
    row = [model, label, str(rate), "yes" if conf and conf[0]["ret"] == 0 and len(conf) == 1 else "NO",
           "%.0f" % conf[0]["ms"] if conf else "-", str(len(run.of("timeout"))), str(len(gps)),
           fmt_max(st["pos"]), fmt_max(st["alt"]), "%.3f" % st["vel"], "%.3f" % st["veld"],
           "%.2f/%.2f" % (st.get("eph_med", 0), st.get("epv_med", 0)), "%.1f" % p95(st.get("ratio", [])),
           str(gps[-1]["sats"]) if gps else "-"]
    return name, c, row, run


def fault_case(ctx, model):
    name = "%s faults" % model
    emu = ["--receiver", model, "--protocol", "ubx", "--rate", "5", "--noise", "gaussian",
           "--gaussian-sigma", "%g,%g,%g" % SIGMA]
    run = Run(ctx, name, emu, ["--driver", "ubx"], 17)
    run.start()
    c = Checks()
    t = run.configured_at()
    marks = {}
    if c.check(t is not None, "configure() did not succeed"):
        schedule = [(2, "jam", {"fault": "jam", "db": 12}), (5, "jam-clear", {"clear": "jam"}),
                    (6, "spoof", {"fault": "spoof", "speed_mps": 2, "bearing_deg": 90, "detected": True}),
                    (9.5, "spoof-clear", {"clear": "spoof"}), (10.5, "outage", {"fault": "outage"}),
                    (13, "outage-clear", {"clear": "outage"})]
        for at, label, req in schedule:
            time.sleep(max(0, t + at - time.time()))
            answer = run.control.send(req)
            c.check(answer.get("class") in ("FAULT", "CLEAR"), "control answered %s" % answer)
            marks[label] = time.time()
    run.finish()
    gps = common_checks(run, c, DRIVER_PERIOD_S[model], MODELS[model])
    res = {}
    if marks:
        def window(a, b, lag=1.0):
            return [g for g in gps if marks[a] + lag <= g["wall"] <= marks[b]]
        before = [g for g in gps if g["wall"] < marks["jam"] - 0.2][2:]
        jam = window("jam", "jam-clear")
        base = before[-1] if before else None
        if c.check(base is not None and jam, "no sensor_gps before or during the jam"):
            j = jam[-1]
            res["jam"] = "jamInd %d→%d noise %d→%d" % (base["jam_ind"], j["jam_ind"], base["noise"], j["noise"])
            c.check(j["jam_ind"] > base["jam_ind"] + 50, "jamming_indicator %d under a 12 dB jam (clean %d)" %
                    (j["jam_ind"], base["jam_ind"]))
            c.check(j["noise"] > base["noise"], "noise_per_ms %d under a jam (clean %d)" % (j["noise"], base["noise"]))
            c.check(j["sats"] < base["sats"], "satellites %d under a jam (clean %d)" % (j["sats"], base["sats"]))
            if MODELS[model] == 8:
                c.check(j["agc"] < base["agc"], "AGC %d under a jam (clean %d)" % (j["agc"], base["agc"]))
                res["jam"] += " agc %d→%d" % (base["agc"], j["agc"])
            else:
                c.check(j["jam_state"] == 2, "jamming_state %d under a 12 dB jam (2: warning)" % j["jam_state"])
                res["jam"] += " state %d→%d" % (base["jam_state"], j["jam_state"])
        after_jam = window("jam-clear", "spoof", lag=0.6)
        c.check(after_jam and after_jam[-1]["jam_ind"] == base["jam_ind"], "the jam's RF state stayed after clear")
        spoof = window("spoof", "spoof-clear", lag=2.0)
        if c.check(spoof, "no sensor_gps during the spoof"):
            s = spoof[-1]
            de, dn, du = enu_error(s, run.t0)
            res["spoof"] = "state %d, dragged %.1f m east" % (s["spoof"], de)
            c.check(all(g["spoof"] == 3 for g in spoof), "spoofing_state %s under a detected spoof (3)" %
                    sorted({g["spoof"] for g in spoof}))
            c.check(de > 2.0, "the spoof dragged the position %.1f m east" % de)
            c.check(s["fix"] == 3, "fix %d under a spoof" % s["fix"])
        after = window("spoof-clear", "outage", lag=0.6)
        c.check(after and after[-1]["spoof"] == 0, "spoofing_state after the spoof ended %s" %
                (after[-1]["spoof"] if after else "-"))
        out = window("outage", "outage-clear")
        if c.check(out, "no sensor_gps during the outage (the driver must keep receiving NAV-PVT)"):
            res["outage"] = "fix %s" % sorted({g["fix"] for g in out})
            c.check(all(g["fix"] in (0, 1) for g in out), "fix types %s in an outage" % sorted({g["fix"] for g in out}))
        back = [g for g in gps if g["wall"] > marks["outage-clear"] + 1.5]
        c.check(back and back[-1]["fix"] == 3, "no 3-D fix after the outage")
    row = [model, res.get("jam", "-"), res.get("spoof", "-"), res.get("outage", "-"), str(len(run.of("timeout")))]
    return name, c, row, run


def rtk_case(ctx, model):
    name = "%s RTK" % model
    emu = ["--receiver", model, "--protocol", "ubx", "--rate", "5", "--noise", "gaussian",
           "--gaussian-sigma", "%g,%g,%g" % SIGMA] + (["--rtk-convergence", "1,2"] if model != "ublox-m10" else [])
    run = Run(ctx, name, emu, ["--driver", "ubx"], 10)
    run.start()
    c = Checks()
    t = run.configured_at()
    if c.check(t is not None, "configure() did not succeed"):
        time.sleep(max(0, t + 1 - time.time()))
        k = 0
        while time.time() < t + 8.5:
            run.inject(rtcm_base_epoch(42, int(time.time() * 1000) % 604800000))
            k += 1
            time.sleep(1.0)
    run.finish()
    gps = common_checks(run, c, DRIVER_PERIOD_S[model], MODELS[model])
    end = run.of("end")
    injected = end[0]["injected"] if end else 0
    c.check(injected > 0, "nothing injected (shouldInjectRTCM() false?)")
    fixes = [g["fix"] for g in gps]
    seen = []
    for f in fixes:
        if not seen or seen[-1] != f:
            seen.append(f)
    tail = [g for g in gps if g["wall"] > (t or 0) + 6.5]
    if model == "ublox-m10":
        # PX4 injects into an M10 as into any u-blox (shouldInjectRTCM() is true once configured); a
        # MAX-M10S takes no RTCM3 (SPG 5.10): the fix stays 3-D, no RXM-RTCM (PX4 does not enable it
        # on an M10), and gpsemu counts the frames it ignored.
        c.check(fixes and all(f == 3 for f in fixes[2:]), "fix types %s: an M10 takes no RTCM3 (3 only)" % seen)
        c.check(all(g["rtcm_used"] == 0 for g in gps), "RXM-RTCM reported on an M10")
        log = open(os.path.join(run.dir, "gpsemu.log")).read()
        frames = re.search(r"(\d+) RTCM3 frames \(\d+ bad CRC, (\d+) ignored: ublox-m10 takes no RTCM3\)", log)
        c.check(frames is not None and int(frames.group(1)) > 0 and frames.group(1) == frames.group(2),
                "gpsemu's summary does not say the RTCM3 frames were ignored: %s" %
                (frames.group(0) if frames else "no RTCM3 count"))
        st = position_checks(run, c, [g for g in gps if g["fix"] >= 3])
        row = [model, "→".join(str(f) for f in seen), "%d B" % injected, fmt_max(st["pos"]),
               "%.3f" % (tail[-1]["eph"] if tail else float("nan")),
               "- (%s of %s frames ignored)" % ((frames.group(2), frames.group(1)) if frames else ("?", "?"))]
        return name, c, row, run
    if model == "ublox-f9p":
        c.check(5 in fixes and 6 in fixes, "fix types %s: no RTK float and fixed" % seen)
        c.check(tail and all(g["fix"] == 6 for g in tail), "not RTK fixed at the end: %s" % seen)
        c.check(tail and all(g["eph"] <= 0.02 for g in tail), "eph %.3f m in RTK fixed" % (tail[-1]["eph"] if tail else -1))
    else:  # an M9N: DGNSS only
        c.check(4 in fixes and 5 not in fixes and 6 not in fixes, "fix types %s: an M9N goes DGPS (4) only" % seen)
        c.check(tail and all(g["fix"] == 4 for g in tail), "not DGPS at the end: %s" % seen)
    c.check(any(g["rtcm_used"] == 2 for g in gps), "RXM-RTCM never reported a message used")
    st = position_checks(run, c, [g for g in gps if g["fix"] >= 3])
    row = [model, "→".join(str(f) for f in seen), "%d B" % injected, fmt_max(st["pos"]),
           "%.3f" % (tail[-1]["eph"] if tail else float("nan")), str(max((g["rtcm_used"] for g in gps), default=0))]
    return name, c, row, run


HEADING_FLEET = """
source = "udp:127.0.0.1:{port0}"
rate = 5
fix-quality = "rtk-fixed"
protocol = "ubx"
noise = "none"
[[receiver]]
receiver = "ublox-f9p"
role = "moving-base"
antenna-offset = "-0.5,0,0"
output = "pty:{dir}/base"
source = "udp:127.0.0.1:{port0}"
[[receiver]]
receiver = "ublox-f9p"
role = "rover"
antenna-offset = "0.5,0,0"
output = "pty:{dir}/gps"
source = "udp:127.0.0.1:{port1}"
"""


def heading_case(ctx):
    name = "ublox-f9p moving-base rover heading"
    run = Run(ctx, name, [], ["--driver", "ubx", "--ubx-mode", "rover-mb-uart1"], 10,
              fleet_config=HEADING_FLEET, pose_ports=2, base_link="base")
    stop = threading.Event()

    def forward():  # PX4: the moving base's RTCM3 (gotRTCMMessage) published and injected into the rover
        fd = None
        buf = b""
        while not stop.is_set():
            if fd is None:
                try:
                    fd = os.open(run.base, os.O_RDONLY | os.O_NOCTTY | os.O_NONBLOCK)
                    tty.setraw(fd)
                except OSError:
                    time.sleep(0.05)
                    continue
            try:
                buf += os.read(fd, 65536)
            except BlockingIOError:
                time.sleep(0.01)
                continue
            frames, buf = rtcm_frames(buf)
            for fr in frames:
                run.inject(fr)
        if fd is not None:
            os.close(fd)

    run.start()
    fwd = threading.Thread(target=forward, daemon=True)
    fwd.start()
    run.finish()
    stop.set()
    c = Checks()
    gps = common_checks(run, c, 0.2, MODELS["ublox-f9p"])
    rel = run.of("rel")
    valid = [r for r in rel if r["heading_valid"]]
    c.check(len(valid) >= 0.5 * len(rel) > 0, "%d of %d NAV-RELPOSNED with a valid heading" % (len(valid), len(rel)))
    want = math.radians(YAW_DEG)
    worst = 0.0
    for g in gps:
        if g["heading"] is not None:
            err = abs((g["heading"] - want + math.pi) % (2 * math.pi) - math.pi)
            worst = max(worst, err)
            c.check(err <= max(3 * (g["heading_acc"] or 0), math.radians(1.0)),
                    "heading %.2f deg, yaw %.1f (accuracy %.2f deg)" %
                    (math.degrees(g["heading"]), YAW_DEG, math.degrees(g["heading_acc"] or 0)))
    with_heading = [g for g in gps if g["heading"] is not None]
    c.check(len(with_heading) >= 0.5 * len(gps) > 0, "%d of %d sensor_gps with a heading" % (len(with_heading), len(gps)))
    lengths = [r["length"] for r in valid]
    if lengths:
        c.check(abs(lengths[-1] - 1.0) <= 0.05, "baseline %.3f m, the antennas 1 m apart" % lengths[-1])
    row = ["%d/%d" % (len(with_heading), len(gps)), "%.2f°" % math.degrees(worst),
           "%.3f m" % (lengths[-1] if lengths else float("nan")), "%d B" % (run.of("end")[0]["injected"] if run.of("end") else 0)]
    return name, c, row, run


def nmea_case(ctx, rate, sentences=None):
    label = "default" if sentences is None else sentences
    name = "nmea %s %dHz" % (label, rate)
    emu = ["--rate", str(rate), "--noise", "gaussian", "--gaussian-sigma", "%g,%g,%g" % SIGMA]
    if sentences:
        emu += ["--sentences", sentences]
    # SER_GPS1_BAUD 115200, as a vehicle with an NMEA receiver is set up (README: a baud that fits):
    # with 0, the NMEA driver's auto-baud takes the first baud it tries (9600) on a pty and reads
    # as slowly as a 9600 baud line, which a 10 Hz default set does not fit.
    run = Run(ctx, name, emu, ["--driver", "nmea", "--baud", "115200"], ctx.seconds)
    run.start()
    run.finish()
    c = Checks()
    gps = common_checks(run, c, 1.0 / rate)
    st = position_checks(run, c, gps, vertical_velocity=False)
    if gps and run.status:
        used = run.status["receivers"][0].get("satellites_used")
        c.check(gps[-1]["sats"] == used, "satellites_used %d, gpsemu used %s" % (gps[-1]["sats"], used))
    if sentences and "GST" in sentences:
        gst = {round(math.hypot(a, b), 2) for a, b, _ in gst_sigmas(run)}
        c.check(gst and all(round(g["eph"], 2) in gst for g in gps[1:]),
                "eph not the hypot of a GST's sigmas (%s)" % sorted({round(g["eph"], 2) for g in gps})[:5])
    eph = "%.2f/%.2f" % (sorted(st["eph"])[len(st["eph"]) // 2], sorted(st["epv"])[len(st["epv"]) // 2]) if st["eph"] else "-"
    conf = run.of("configure")
    row = [label, str(rate), "yes" if conf and conf[0]["ret"] == 0 and len(conf) == 1 else "NO",
           str(len(run.of("timeout"))), str(len(gps)), fmt_max(st["pos"]), fmt_max(st["alt"]), "%.3f" % st["vel"],
           eph, str(gps[-1]["sats"]) if gps else "-"]
    return name, c, row, run


# ---------------------------------------------------------------- main

class Context:
    pass


def table(title, header, rows):
    out = ["", "### " + title, "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(out)


def main(argv):
    ap = argparse.ArgumentParser(prog="tools/driver-check", description=__doc__.split("\n\n")[0])
    ap.add_argument("autopilot", choices=["px4"])
    ap.add_argument("--px4-gpsdrivers", metavar="DIR", default=os.environ.get("GPSEMU_PX4_GPSDRIVERS"),
                    help="a PX4-GPSDrivers checkout (default: $GPSEMU_PX4_GPSDRIVERS)")
    ap.add_argument("--gpsemu", default=os.path.join(os.environ.get("GPSEMU_BUILD_DIR", os.path.join(ROOT, "build")),
                                                   "emulator", "gpsemu"))
    ap.add_argument("--boots", type=int, default=2, help="boots of each model x start state x rate (default 2)")
    ap.add_argument("--seconds", type=float, default=6, help="seconds the driver runs in each boot (default 6)")
    ap.add_argument("--quick", action="store_true", help="one boot, --rate 1 and 10, factory and ubx only")
    ap.add_argument("--only", default="", help="run only the cases whose name contains this text")
    ap.add_argument("--seed", type=int, default=None, help="seed of the boot phases (default: random, printed)")
    ap.add_argument("--keep", metavar="DIR", help="keep each failed run's logs and wire trace here")
    a = ap.parse_args(argv)
    os.environ["TZ"] = "UTC"  # the drivers turn NAV-PVT's date into time with mktime(), as on PX4 (UTC)
    if not a.px4_gpsdrivers:
        print("driver-check: skipped: no PX4-GPSDrivers checkout (--px4-gpsdrivers DIR or GPSEMU_PX4_GPSDRIVERS)")
        return SKIP
    if not os.path.isdir(a.px4_gpsdrivers):
        print("driver-check: --px4-gpsdrivers %s: not a directory" % a.px4_gpsdrivers, file=sys.stderr)
        return 2
    if not os.access(a.gpsemu, os.X_OK):
        print("driver-check: no gpsemu binary at %s (build first, or --gpsemu)" % a.gpsemu, file=sys.stderr)
        return 2
    ctx = Context()
    ctx.gpsemu = a.gpsemu
    ctx.seconds = a.seconds
    ctx.keep = a.keep
    seed = a.seed if a.seed is not None else random.randrange(1, 10 ** 6)
    ctx.rng = random.Random(seed)
    build_dir = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(a.gpsemu))), "driver-check", "px4")
    ctx.harness = build_harness(a.px4_gpsdrivers, build_dir)
    ctx.tmp = tempfile.mkdtemp(prefix="driver-check_")
    commit = gpsdrivers_commit(a.px4_gpsdrivers)
    print("driver-check px4: PX4-GPSDrivers %s (%s), gpsemu %s, seed %d" % (commit, a.px4_gpsdrivers, a.gpsemu, seed))

    boots = 1 if a.quick else a.boots
    rates = [1, 10] if a.quick else [1, 5, 10]
    states = ["factory", "ubx"] if a.quick else ["factory", "ubx", "nmea+ubx"]
    plan = []
    for model in MODELS:
        for state in states:
            if model == "generic" and state == "factory":
                continue
            for rate in rates:
                for boot in range(1, boots + 1):
                    plan.append(("matrix", lambda m=model, s=state, r=rate, b=boot: matrix_case(ctx, m, s, r, b),
                                 "%s %s %dHz #%d" % (model, state, rate, boot)))
    # PX4 asked for a rate (GPS_UBX_RATE): 10 Hz on the u-blox 9s; 5 Hz on the M10, whose default
    # is already its fastest, 10 Hz.
    for model, ubx_rate in [("ublox-m9n", 10), ("ublox-f9p", 10), ("ublox-m10", 5)]:
        for boot in range(1, boots + 1):
            plan.append(("matrix", lambda m=model, b=boot, u=ubx_rate: matrix_case(ctx, m, "ubx", 1, b, ubx_rate=u),
                         "%s ubx, GPS_UBX_RATE %d 1Hz #%d" % (model, ubx_rate, boot)))
    for model in MODELS:
        plan.append(("faults", lambda m=model: fault_case(ctx, m), "%s faults" % model))
    for model in ["ublox-f9p", "ublox-m9n", "ublox-m10"]:
        plan.append(("rtk", lambda m=model: rtk_case(ctx, m), "%s RTK" % model))
    plan.append(("heading", lambda: heading_case(ctx), "ublox-f9p moving-base rover heading"))
    for rate in [5, 10]:
        plan.append(("nmea", lambda r=rate: nmea_case(ctx, r), "nmea default %dHz" % rate))
    plan.append(("nmea", lambda: nmea_case(ctx, 5, "RMC,VTG,GGA,GSA,GSV,GLL,GST"), "nmea RMC,VTG,GGA,GSA,GSV,GLL,GST 5Hz"))
    plan = [p for p in plan if a.only in p[2]]

    rows = {"matrix": {}, "faults": [], "rtk": [], "heading": [], "nmea": []}
    failed = []
    started = time.time()
    for kind, fn, label in plan:
        name, c, row, run = fn()
        ok = not c.failures
        run.keep(not ok)
        print("%-45s %s%s" % (name, "pass" if ok else "FAIL", "" if ok else ": " + "; ".join(sorted(set(c.failures))[:4])),
              flush=True)
        if not ok:
            failed.append(name)
        result = "pass" if ok else "**FAIL**"
        if kind == "matrix":
            key = tuple(row[:3])
            prev = rows["matrix"].get(key)
            if prev is None:
                rows["matrix"][key] = row + [result, 1]
            else:  # boots of one cell: the worst figures, the count
                for i in (6,):
                    prev[i] = str(int(prev[i]) + int(row[i]))
                for i in (7, 8, 9, 10, 12):
                    prev[i] = max(prev[i], row[i], key=float)
                prev[4] = max(prev[4], row[4], key=lambda v: float(v) if v != "-" else 0)
                prev[5] = str(int(prev[5]) + int(row[5]))
                prev[3] = "yes" if prev[3] == "yes" and row[3] == "yes" else "NO"
                prev[14] = prev[14] if ok else result
                prev[15] += 1
        else:
            rows[kind].append(row + [result])
    out = []
    if rows["matrix"]:
        out.append(table("u-blox driver: each model x start state x --rate (boots at random phases)",
                         ["model", "start", "--rate", "configure 1st", "configure ms (max)", "timeouts",
                          "sensor_gps", "horiz. err max m", "vert. err max m", "vel err max m/s",
                          "velD err max m/s", "eph/epv m (median)", "err/eph p95", "sats", "result", "boots"],
                         [r[:14] + [r[14], str(r[15])] for r in rows["matrix"].values()]))
    if rows["faults"]:
        out.append(table("Faults from the control socket (--protocol ubx, 5 Hz)",
                         ["model", "jam 12 dB (MON-RF / MON-HW)", "spoof 2 m/s detected", "outage", "timeouts",
                          "result"], rows["faults"]))
    if rows["rtk"]:
        out.append(table("RTK: RTCM3 (1005 + MSM4) written through the driver's injection path",
                         ["model", "fix types seen", "injected", "horiz. err max m", "eph at end m",
                          "RXM-RTCM msgUsed", "result"], rows["rtk"]))
    if rows["heading"]:
        out.append(table("Moving-base rover (GPS_UBX_MODE 3: rover on UART1, the base's RTCM3 injected)",
                         ["sensor_gps with heading", "heading err max", "baseline", "injected", "result"],
                         rows["heading"]))
    if rows["nmea"]:
        out.append(table("PX4's NMEA driver (GPS_x_PROTOCOL 6)",
                         ["sentences", "--rate", "configure 1st", "timeouts", "sensor_gps", "horiz. err max m",
                          "vert. err max m", "vel err max m/s", "eph/epv m", "sats", "result"], rows["nmea"]))
    print("\n".join(out))
    print("\n%d of %d runs passed in %.0f s%s" % (len(plan) - len(failed), len(plan), time.time() - started,
                                                ("; failed: " + ", ".join(failed)) if failed else ""))
    shutil.rmtree(ctx.tmp, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
