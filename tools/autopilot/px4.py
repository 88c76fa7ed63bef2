"""PX4's side of the autopilot loop: build PX4 SITL in a checkout, generate the MAVLink module from
its own message definitions, and start one SITL vehicle simulated by SIH (PX4's simulator inside
the px4 process), optionally with its GPS on gpsemu's pty and gpsemu fed by SIH's ground truth.

PX4 SITL with SIH sends HIL_STATE_QUATERNION (SIH's truth) at 25 Hz to UDP 19410 + instance
(px4-rc.mavlink, for a viewer): gpsemu listens there (--source mavlink:udp:...). The vehicle's own
simulated GPS is turned off (SENS_EN_GPSSIM 0) and PX4's real GPS driver, `gps`, is started on
gpsemu's pty. Both go through an airframe of our own: each flight gets a rootfs of symbolic links
to the build's etc/ with that airframe added, so the checkout and its build are left as they are.
"""

import os
import pathlib
import signal
import socket
import subprocess
import time

from sitl import HOME, Process, Stop, generate_mavlink

AIRFRAME_ID = 10089  # our airframe (the SIH quadrotor with GPS 1 on gpsemu); checked to be free
NEEDED = ["src/drivers/gps/devices/src/ubx.cpp", "src/modules/mavlink/mavlink/message_definitions/v1.0/common.xml",
          "src/modules/mavlink/mavlink/pymavlink/generator/mavgen.py", "src/lib/events/libevents/libs"]


def check_checkout(px4):
    top = pathlib.Path(px4)
    if not (top / "boards/px4/sitl").is_dir() or not (top / "src/modules/simulation/simulator_sih").is_dir():
        raise Stop(f"--px4 {px4}: not a PX4-Autopilot checkout (no boards/px4/sitl, no simulator_sih)")
    missing = [m for m in NEEDED if not (top / m).exists()]
    if missing:
        raise Stop(f"--px4 {px4}: submodules missing: {', '.join(missing)} "
                   "(git submodule update --init --recursive)")


def commit_of(px4):
    out = subprocess.run(["git", "-C", px4, "describe", "--always", "--tags", "--dirty"], capture_output=True,
                         text=True)
    return out.stdout.strip() if out.returncode == 0 else "unknown (not a git checkout)"


def build(px4, config, jobs, log):
    """Builds bin/px4 of `config` (px4_sitl_default, or px4_sitl_<variant>) unless it is there;
    returns the build directory."""
    build_dir = pathlib.Path(px4) / "build" / config
    if (build_dir / "bin/px4").exists():
        return build_dir
    # PX4's generators (uORB, parameters, MAVLink, events) run with Debian's python3 (empy 3).
    env = dict(os.environ, PATH="/usr/bin:" + os.environ.get("PATH", ""), GIT_SUBMODULES_ARE_EVIL="1")
    with open(log, "w") as out:
        print(f"building PX4 SITL ({config}) in {px4} (log {log}); this takes long", flush=True)
        if not (build_dir / "build.ninja").exists():
            if subprocess.run(["cmake", "-S", px4, "-B", str(build_dir), "-G", "Ninja", f"-DCONFIG={config}",
                               "-DPython3_EXECUTABLE=/usr/bin/python3", "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                              env=env, stdout=out, stderr=subprocess.STDOUT).returncode != 0:
                raise Stop(f"cmake failed for {config} in {px4}: see {log}")
        if subprocess.run(["nice", "ninja", "-C", str(build_dir), f"-j{jobs}", "px4"], env=env, stdout=out,
                          stderr=subprocess.STDOUT).returncode != 0:
            raise Stop(f"building px4 ({config}) failed in {px4}: see {log}")
    return build_dir


def mavlink_module(px4, work):
    """pymavlink's Python module for common.xml, generated from the checkout's mavlink submodule."""
    return generate_mavlink(pathlib.Path(px4) / "src/modules/mavlink/mavlink", "common", "px4_mavlink", work)


def _udp_free(port):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
            return True
        except OSError:
            return False


def free_instance():
    """A PX4 instance whose UDP ports (ground station 18570 + I, SIH viewer 19410 + I, offboard
    14580 + I) are free."""
    for instance in range(0, 10):
        if all(_udp_free(base + instance) for base in (18570, 19410, 14580, 14280, 13030, 19450)):
            return instance
    raise Stop("no free PX4 SITL instance (UDP ports 18570..18579 in use)")


def airframe(gps_protocol):
    """Our airframe: the SIH quadrotor, its simulated GPS off when GPS 1 is gpsemu."""
    lines = ["#!/bin/sh", "# gpsemu's autopilot loop: the SIH quadrotor (10040) with GPS 1 on gpsemu",
             ". ${R}etc/init.d-posix/airframes/10040_sihsim_quadx",
             "param set SENS_EN_GPSSIM 0" if gps_protocol else "# GPS 1: SIH's own simulated GPS (baseline)"]
    return "\n".join(lines) + "\n"


def airframe_post(gps_protocol, pty, params):
    lines = ["#!/bin/sh", "# gpsemu's autopilot loop, after PX4's start-up (rcS runs <airframe>.post)"]
    lines += [f"param set {p}" for p in params]
    if gps_protocol:
        # PX4's own GPS driver on gpsemu's pty, as on a vehicle's serial port. u-blox: -b 0, the
        # driver finds the receiver's baud and sets its own; NMEA: a fixed baud (its auto-baud stays
        # at 9600 on a pty, too slow for the sentences: gpsemu keeps a pty to the baud it is set to).
        baud = 0 if gps_protocol == "ubx" else 115200
        lines.append(f"gps start -d {pty} -b {baud} -p {gps_protocol}")
    return "\n".join(lines) + "\n"


def overlay_rootfs(build_dir, data, gps_protocol, pty, params):
    """data/etc: symbolic links to the build's etc/, with our airframe added to its airframes."""
    etc = pathlib.Path(build_dir) / "etc"
    (data / "etc/init.d-posix/airframes").mkdir(parents=True, exist_ok=True)
    for entry in etc.iterdir():
        if entry.name != "init.d-posix":
            _link(entry, data / "etc" / entry.name)
    for entry in (etc / "init.d-posix").iterdir():
        if entry.name != "airframes":
            _link(entry, data / "etc/init.d-posix" / entry.name)
    for entry in (etc / "init.d-posix/airframes").iterdir():
        if entry.name.startswith(f"{AIRFRAME_ID}_"):
            raise Stop(f"airframe {AIRFRAME_ID} is taken in this PX4 ({entry.name}): change AIRFRAME_ID in {__file__}")
        _link(entry, data / "etc/init.d-posix/airframes" / entry.name)
    ours = data / f"etc/init.d-posix/airframes/{AIRFRAME_ID}_sihsim_gpsemu"
    ours.write_text(airframe(gps_protocol))
    pathlib.Path(str(ours) + ".post").write_text(airframe_post(gps_protocol, pty, params))
    return "sihsim_gpsemu"


def _link(target, link):
    if not link.exists() and not link.is_symlink():
        link.symlink_to(target)


class Rig:
    """One PX4 SITL vehicle (and gpsemu when gpsemu_args is given) in its own directory."""

    def __init__(self, build_dir, work, name, gpsemu=None, gpsemu_args=None, gps_protocol=None, params=()):
        self.dir = pathlib.Path(work) / name
        self.dir.mkdir(parents=True, exist_ok=True)
        self.instance = free_instance()
        self.gpsemu = None
        self.ctl = None
        # PX4's gps driver keeps its device's path in 20 characters (gps.cpp: char _port[20]): a
        # short link in /tmp, one an instance.
        pty = pathlib.Path(f"/tmp/gpsemu-px4-{self.instance}")
        if pty.is_symlink() and not pty.exists():
            pty.unlink()  # a link left by a run that was killed
        if gpsemu_args is not None:
            self.ctl = str(self.dir / "gpsemu.ctl")
            self.gpsemu_log = self.dir / "gpsemu.log"
            # SIH's truth comes to 19410 + instance over UDP (HIL_STATE_QUATERNION at 25 Hz).
            args = [gpsemu, "--source", f"mavlink:udp:127.0.0.1:{19410 + self.instance}",
                    "--output", f"pty:{pty}", "--control", f"unix:{self.ctl}", "--control-idle-timeout", "0",
                    "--origin", f"{HOME[0]},{HOME[1]},{HOME[2]}"] + gpsemu_args
            (self.dir / "gpsemu.cmd").write_text(" ".join(args) + "\n")
            self.gpsemu = Process(args, self.dir, self.gpsemu_log)
            deadline = time.monotonic() + 10
            while not pty.exists():
                if self.gpsemu.proc.poll() is not None or time.monotonic() > deadline:
                    raise Stop(f"gpsemu did not open its pty: see {self.gpsemu_log}")
                time.sleep(0.1)
        model = overlay_rootfs(build_dir, self.dir / "data", gps_protocol if gpsemu_args is not None else None,
                               pty, params)
        rootfs = self.dir / "rootfs"
        rootfs.mkdir(exist_ok=True)
        env = dict(os.environ, PX4_SIM_MODEL=model, PX4_SIMULATOR="sihsim", PX4_HOME_LAT=str(HOME[0]),
                   PX4_HOME_LON=str(HOME[1]), PX4_HOME_ALT=str(HOME[2]))
        cmd = [str(pathlib.Path(build_dir) / "bin/px4"), "-d", "-i", str(self.instance), "-w", str(rootfs),
               str(self.dir / "data/etc")]  # px4's data path: the etc/ its rootfs links to
        (self.dir / "px4.cmd").write_text(f"PX4_SIM_MODEL={model} PX4_SIMULATOR=sihsim " + " ".join(cmd) + "\n")
        self.px4_log = self.dir / "px4.log"
        self.px4 = Process(cmd, self.dir, self.px4_log, env=env)

    def px4_lines(self, *needles):
        text = self.px4_log.read_text(errors="replace") if self.px4_log.exists() else ""
        return [line for line in text.splitlines() if any(n in line for n in needles)]

    def stop(self):
        if self.px4.proc.poll() is None:
            self.px4.proc.send_signal(signal.SIGINT)  # px4 shuts its modules down on SIGINT
        self.px4.stop()
        return self.gpsemu.stop() if self.gpsemu else None
