"""ArduPilot's side of the autopilot loop: build ArduCopter SITL in a checkout, generate the
MAVLink module from its own message definitions, and start one SITL vehicle (optionally with its
GPS port on gpsemu's pty, gpsemu fed by the vehicle's SIM_STATE)."""

import importlib
import os
import pathlib
import socket
import subprocess
import sys
import time

HOME = (-35.363261, 149.165230, 584.0, 353.0)  # ArduPilot SITL's default home (CMAC), heading deg

# The submodules the SITL build needs (ArduPilot's .gitmodules paths).
NEEDED_MODULES = ["modules/waf/waf-light", "modules/mavlink/message_definitions/v1.0/ardupilotmega.xml",
                  "modules/mavlink/pymavlink/generator/mavgen.py", "modules/DroneCAN/DSDL",
                  "modules/DroneCAN/dronecan_dsdlc", "modules/DroneCAN/libcanard",
                  "modules/DroneCAN/pydronecan", "modules/littlefs"]


class Stop(Exception):
    """A problem with the set-up (not a test result): the tool exits with status 2."""


def check_checkout(ardupilot):
    top = pathlib.Path(ardupilot)
    if not (top / "waf").exists() or not (top / "ArduCopter").is_dir():
        raise Stop(f"--ardupilot {ardupilot}: not an ArduPilot checkout (no waf, no ArduCopter/)")
    missing = [m for m in NEEDED_MODULES if not (top / m).exists()]
    if missing:
        raise Stop(f"--ardupilot {ardupilot}: submodules missing: {', '.join(missing)} "
                   "(git submodule update --init --recursive)")


def commit_of(ardupilot):
    out = subprocess.run(["git", "-C", ardupilot, "rev-parse", "HEAD"], capture_output=True, text=True)
    return out.stdout.strip() if out.returncode == 0 else "unknown (not a git checkout)"


def build(ardupilot, jobs, log):
    """Builds bin/arducopter for the sitl board unless it is there; returns its path."""
    binary = pathlib.Path(ardupilot) / "build/sitl/bin/arducopter"
    if binary.exists():
        return binary
    waf = [sys.executable, "./waf"]
    with open(log, "w") as out:
        if not (pathlib.Path(ardupilot) / "build/c4che/sitl_cache.py").exists():
            print(f"building ArduCopter SITL in {ardupilot} (log {log}); this takes long", flush=True)
            if subprocess.run(waf + ["configure", "--board", "sitl", "--disable-networking",
                                     "--no-submodule-update"], cwd=ardupilot, stdout=out,
                              stderr=subprocess.STDOUT).returncode != 0:
                raise Stop(f"waf configure failed in {ardupilot}: see {log}")
        if subprocess.run(["nice"] + waf + ["copter", f"-j{jobs}"], cwd=ardupilot, stdout=out,
                          stderr=subprocess.STDOUT).returncode != 0:
            raise Stop(f"./waf copter failed in {ardupilot}: see {log}")
    return binary


def mavlink_module(ardupilot, work):
    """pymavlink's Python module for ardupilotmega.xml, generated from the checkout into work."""
    mavlink_dir = pathlib.Path(ardupilot) / "modules/mavlink"
    out = pathlib.Path(work) / "apm_mavlink.py"
    if not out.exists():
        env = dict(os.environ, PYTHONPATH=str(mavlink_dir))
        result = subprocess.run([sys.executable, "-m", "pymavlink.tools.mavgen", "--lang", "Python3",
                                 "--wire-protocol", "2.0", "--output", str(out),
                                 str(mavlink_dir / "message_definitions/v1.0/ardupilotmega.xml")],
                                env=env, capture_output=True, text=True)
        if result.returncode != 0:
            raise Stop(f"mavgen failed: {result.stderr.strip()[-500:]}")
    sys.path.insert(0, str(work))
    sys.path.insert(1, str(mavlink_dir))
    return importlib.import_module("apm_mavlink")


def port_free(port):
    with socket.socket() as s:
        try:
            s.bind(("127.0.0.1", port))
            return True
        except OSError:
            return False


def free_instance():
    """A SITL instance number whose TCP ports (5760 + 10 I .. 5763 + 10 I) are free."""
    for instance in range(1, 30):
        if all(port_free(5760 + 10 * instance + k) for k in range(4)):
            return instance
    raise Stop("no free SITL instance (TCP ports 5770..6053 in use)")


def write_params(path, gpsemu, extra):
    """The vehicle's parameters beside ArduPilot's copter.parm: the streams the loop reads."""
    lines = [
        # First MAVLink port (the mission's link): truth, attitude, position, status, EKF.
        "MAV1_EXTRA1 20", "MAV1_POSITION 20", "MAV1_EXT_STAT 5", "MAV1_EXTRA3 5",
        "MAV1_RAW_SENS 0", "MAV1_RC_CHAN 0", "MAV1_EXTRA2 0",
        # Second MAVLink port (gpsemu's pose source, --source mavlink:tcp): SIM_STATE at 50 Hz
        # (gpsemu asks for it with MAV_CMD_SET_MESSAGE_INTERVAL as a ground station would) and the
        # ATTITUDE and SIMSTATE of the EXTRA1 stream.
        "MAV2_EXTRA1 50", "MAV2_RAW_SENS 0", "MAV2_EXT_STAT 0", "MAV2_RC_CHAN 0", "MAV2_RAW_CTRL 0",
        "MAV2_POSITION 0", "MAV2_EXTRA2 0", "MAV2_EXTRA3 0", "MAV2_PARAMS 0", "MAV2_ADSB 0",
    ]
    lines.append("LOG_DISARMED 1")  # the dataflash log (logs/*.BIN) from boot: GPS timing before arming
    if gpsemu:
        lines.append("SIM_GPS1_ENABLE 0")  # SITL's own GPS off: GPS 1 is gpsemu on SERIAL3
    pathlib.Path(path).write_text("\n".join(lines + extra) + "\n")


class Process:
    def __init__(self, args, cwd, log, env=None):
        self.log = open(log, "w")
        self.proc = subprocess.Popen(args, cwd=cwd, stdout=self.log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, env=env)

    def stop(self, timeout_s=10.0):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout_s)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log.close()
        return self.proc.returncode


class Rig:
    """One SITL vehicle (and gpsemu when gpsemu_args is given) in its own directory."""

    def __init__(self, binary, ardupilot, work, name, gpsemu=None, gpsemu_args=None,
                 params=()):
        self.dir = pathlib.Path(work) / name
        self.dir.mkdir(parents=True, exist_ok=True)
        self.instance = free_instance()
        self.mavlink_port = 5760 + 10 * self.instance
        self.gpsemu = None
        self.ctl = None
        param_file = self.dir / "loop.parm"
        write_params(param_file, gpsemu_args is not None, list(params))
        sitl = [str(binary), "--model", "quad", "--speedup", "1", "-w", "-I", str(self.instance),
                "--home", ",".join(str(v) for v in HOME),
                "--defaults", f"{ardupilot}/Tools/autotest/default_params/copter.parm,{param_file}"]
        if gpsemu_args is not None:
            pty = self.dir / "gps.pty"
            self.ctl = str(self.dir / "gpsemu.ctl")
            self.gpsemu_log = self.dir / "gpsemu.log"
            # SITL's second MAVLink port (SERIAL1, TCP 5762 + 10 x instance): gpsemu connects, retries
            # every second until SITL listens, and asks for SIM_STATE itself.
            args = [gpsemu, "--source", f"mavlink:tcp:127.0.0.1:{self.mavlink_port + 2}",
                    "--output", f"pty:{pty}", "--control", f"unix:{self.ctl}",
                    "--control-idle-timeout", "0",
                    "--origin", f"{HOME[0]},{HOME[1]},{HOME[2]}"] + gpsemu_args
            (self.dir / "gpsemu.cmd").write_text(" ".join(args) + "\n")
            self.gpsemu = Process(args, self.dir, self.gpsemu_log)
            deadline = time.monotonic() + 10
            while not pty.exists():
                if self.gpsemu.proc.poll() is not None or time.monotonic() > deadline:
                    raise Stop(f"gpsemu did not open its pty: see {self.gpsemu_log}")
                time.sleep(0.1)
            sitl.append(f"--serial3=uart:{pty}")
        (self.dir / "sitl.cmd").write_text(" ".join(sitl) + "\n")
        self.sitl = Process(sitl, self.dir, self.dir / "sitl.log")

    def stop(self):
        self.sitl.stop()
        return self.gpsemu.stop() if self.gpsemu else None
