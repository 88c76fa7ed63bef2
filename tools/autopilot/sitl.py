"""ArduPilot's side of the autopilot loop: build ArduCopter SITL in a checkout, generate the
MAVLink module from its own message definitions, and start one SITL vehicle (optionally with its
GPS port on gpsemu's pty, gpsemu fed by the vehicle's SIM_STATE)."""

import importlib
import os
import pathlib
import socket
import subprocess
import sys
import threading
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
        # Second MAVLink port (gpsemu's pose source, through the Forwarder): SIM_STATE at 50 Hz
        # (asked for by the Forwarder) and the ATTITUDE and SIMSTATE of the EXTRA1 stream.
        "MAV2_EXTRA1 50", "MAV2_RAW_SENS 0", "MAV2_EXT_STAT 0", "MAV2_RC_CHAN 0", "MAV2_RAW_CTRL 0",
        "MAV2_POSITION 0", "MAV2_EXTRA2 0", "MAV2_EXTRA3 0", "MAV2_PARAMS 0", "MAV2_ADSB 0",
    ]
    lines.append("LOG_DISARMED 1")  # the dataflash log (logs/*.BIN) from boot: GPS timing before arming
    if gpsemu:
        lines.append("SIM_GPS1_ENABLE 0")  # SITL's own GPS off: GPS 1 is gpsemu on SERIAL3
    pathlib.Path(path).write_text("\n".join(lines + extra) + "\n")


class Forwarder(threading.Thread):
    """What MAVProxy's --out does for sim_vehicle.py: a ground-station link of its own to one SITL
    MAVLink port that asks for SIM_STATE (MAVLink 108: ArduPilot sends it only when asked, it is in
    no stream; the EXTRA1 stream carries SIMSTATE, without altitude and velocity) at 50 Hz and
    forwards every frame it gets (whole frames a datagram) to gpsemu's mavlink:udp port."""

    def __init__(self, mavlink_module, tcp_port, udp_port):
        super().__init__(daemon=True)
        self.m, self.tcp_port, self.udp_port = mavlink_module, tcp_port, udp_port
        self.stopping = threading.Event()
        self.bytes_forwarded = 0
        self.start()

    def run(self):
        out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock = None
        while sock is None and not self.stopping.is_set():
            try:
                sock = socket.create_connection(("127.0.0.1", self.tcp_port), timeout=1.0)
            except OSError:
                time.sleep(0.5)
        if sock is None:
            return

        class _Out:
            def write(self, data):
                sock.sendall(data)
        mav = self.m.MAVLink(_Out(), srcSystem=254, srcComponent=191)
        mav.robust_parsing = True
        sock.settimeout(0.2)
        last_request = 0.0
        while not self.stopping.is_set():
            if time.monotonic() - last_request > 1.0:
                mav.heartbeat_send(self.m.MAV_TYPE_GCS, self.m.MAV_AUTOPILOT_INVALID, 0, 0, 0)
                mav.command_long_send(1, 1, self.m.MAV_CMD_SET_MESSAGE_INTERVAL, 0,
                                      self.m.MAVLINK_MSG_ID_SIM_STATE, 20000, 0, 0, 0, 0, 0)
                last_request = time.monotonic()
            try:
                data = sock.recv(65536)
            except socket.timeout:
                continue
            except OSError:
                break
            if not data:
                break
            # One datagram of whole frames, as MAVProxy sends them (gpsemu drops a frame cut by
            # the end of its datagram): the frames this read completed.
            frames = b"".join(bytes(msg.get_msgbuf()) for msg in mav.parse_buffer(data) or [])
            if frames:
                out.sendto(frames, ("127.0.0.1", self.udp_port))
                self.bytes_forwarded += len(frames)
        sock.close()

    def stop(self):
        self.stopping.set()
        self.join(2.0)


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Process:
    def __init__(self, args, cwd, log):
        self.log = open(log, "w")
        self.proc = subprocess.Popen(args, cwd=cwd, stdout=self.log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL)

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

    def __init__(self, binary, ardupilot, work, name, gpsemu=None, gpsemu_args=None, mavlink_module=None,
                 params=()):
        self.dir = pathlib.Path(work) / name
        self.dir.mkdir(parents=True, exist_ok=True)
        self.instance = free_instance()
        self.mavlink_port = 5760 + 10 * self.instance
        self.gpsemu = None
        self.ctl = None
        self.forwarder = None
        param_file = self.dir / "loop.parm"
        write_params(param_file, gpsemu_args is not None, list(params))
        sitl = [str(binary), "--model", "quad", "--speedup", "1", "-w", "-I", str(self.instance),
                "--home", ",".join(str(v) for v in HOME),
                "--defaults", f"{ardupilot}/Tools/autotest/default_params/copter.parm,{param_file}"]
        if gpsemu_args is not None:
            pty = self.dir / "gps.pty"
            self.ctl = str(self.dir / "gpsemu.ctl")
            self.gpsemu_log = self.dir / "gpsemu.log"
            udp_port = free_udp_port()
            args = [gpsemu, "--source", f"mavlink:udp:127.0.0.1:{udp_port}",
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
        if gpsemu_args is not None:
            self.forwarder = Forwarder(mavlink_module, self.mavlink_port + 2, udp_port)

    def stop(self):
        if self.forwarder:
            self.forwarder.stop()
        self.sitl.stop()
        return self.gpsemu.stop() if self.gpsemu else None
