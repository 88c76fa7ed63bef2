"""A MAVLink ground station for the autopilot loop: one link to an ArduPilot SITL (TCP; PX4's
subclass in px4_vehicle.py talks UDP), what it reports (recorded with the wall time it arrived)
and the commands a scripted mission needs.

The MAVLink messages come from pymavlink's generator run on the ArduPilot checkout's own message
definitions (ardupilot_loop.py generates the module); this file holds no MAVLink definitions.
"""

import math
import socket
import time

EARTH_RADIUS_M = 6378137.0

COPTER_MODES = {0: "STABILIZE", 2: "ALT_HOLD", 3: "AUTO", 4: "GUIDED", 5: "LOITER", 6: "RTL",
                9: "LAND", 16: "POSHOLD", 17: "BRAKE", 21: "SMART_RTL"}
GUIDED, LAND = 4, 9

# EKF_STATUS_REPORT flags (MAVLink EKF_STATUS_FLAGS) the report names.
EKF_FLAG_NAMES = {1: "attitude", 2: "vel_horiz", 4: "vel_vert", 8: "pos_horiz_rel", 16: "pos_horiz_abs",
                  32: "pos_vert_abs", 64: "pos_vert_agl", 128: "const_pos_mode", 256: "pred_pos_horiz_rel",
                  512: "pred_pos_horiz_abs", 1024: "uninitialized", 32768: "gps_glitching"}
EKF_NAV_GOOD = 1 | 2 | 8 | 16 | 32  # attitude, horizontal velocity, relative and absolute position, height
EKF_GPS_GLITCHING = 32768
EKF_CONST_POS_MODE = 128
SENSOR_GPS = 32                  # MAV_SYS_STATUS_SENSOR_GPS
SENSOR_PREARM_CHECK = 0x10000000  # MAV_SYS_STATUS_PREARM_CHECK: ArduPilot's pre-arm checks pass


def metres_between(lat1_deg, lon1_deg, lat2_deg, lon2_deg):
    """(north_m, east_m) from point 1 to point 2, flat earth (the loop's distances are < 1 km)."""
    north_m = math.radians(lat2_deg - lat1_deg) * EARTH_RADIUS_M
    east_m = math.radians(lon2_deg - lon1_deg) * EARTH_RADIUS_M * math.cos(math.radians(lat1_deg))
    return north_m, east_m


class _SocketFile:
    """pymavlink's MAVLink object writes its frames to a file; this one is the TCP socket."""

    def __init__(self, sock):
        self.sock = sock

    def write(self, data):
        self.sock.sendall(data)


class Vehicle:
    """The link to one SITL vehicle and everything it reported, with the wall time of arrival."""

    def __init__(self, mavlink_module, host, port, connect_timeout_s=60.0, sock=None):
        """A TCP link to host:port (ArduPilot SITL), or `sock`, a link already made (PX4's UDP)."""
        self.m = mavlink_module
        deadline = time.monotonic() + connect_timeout_s
        while sock is None:
            try:
                sock = socket.create_connection((host, port), timeout=2.0)
            except OSError as error:
                if time.monotonic() > deadline:
                    raise RuntimeError(f"cannot connect to SITL at {host}:{port}: {error}") from error
                time.sleep(0.5)
        self.sock = sock
        self.sock.setblocking(False)
        self.mav = mavlink_module.MAVLink(_SocketFile(self.sock), srcSystem=255, srcComponent=190)
        self.mav.robust_parsing = True
        self.t0 = time.monotonic()
        self.target_system = 1
        self.last_heartbeat_sent = 0.0
        # What the vehicle reported (None until it has).
        self.armed = False
        self.mode = None
        self.gps = None           # GPS_RAW_INT
        self.ekf_flags = None     # EKF_STATUS_REPORT flags
        self.sys_status = None
        self.position = None      # GLOBAL_POSITION_INT
        self.local = None         # LOCAL_POSITION_NED
        self.attitude_boot_ms = None
        # Time series: truth (SIM_STATE, timed by the ATTITUDE of the same stream pass) and the
        # EKF's position (GLOBAL_POSITION_INT) and the GPS's (GPS_RAW_INT), each (boot_ms, lat, lon, alt_m).
        self.truth = []
        self.ekf = []
        self.gps_track = []
        self.events = []          # (t_s, kind, text): STATUSTEXT, mode, arming, EKF flags, GPS fix
        self.statustexts = []     # (t_s, severity, text)
        self.acks = []            # (t_s, command, result)
        self.params = {}

    # ---- time and input
    def now(self):
        """Seconds since the link was opened (wall clock)."""
        return time.monotonic() - self.t0

    def boot_ms(self):
        return self.attitude_boot_ms if self.attitude_boot_ms is not None else 0

    def pump(self, duration_s=0.05):
        """Read and record whatever arrives for duration_s; sends the ground station's heartbeat."""
        end = time.monotonic() + duration_s
        while True:
            if time.monotonic() - self.last_heartbeat_sent > 1.0:
                self.mav.heartbeat_send(self.m.MAV_TYPE_GCS, self.m.MAV_AUTOPILOT_INVALID, 0, 0, 0)
                if not self.truth:
                    self.request_truth()
                self.last_heartbeat_sent = time.monotonic()
            try:
                data = self.sock.recv(65536)
                if not data:
                    raise RuntimeError("SITL closed the MAVLink connection")
                for msg in self.mav.parse_buffer(data) or []:
                    self._record(msg)
            except BlockingIOError:
                time.sleep(0.005)
            except OSError as error:
                raise RuntimeError(f"MAVLink connection to SITL lost: {error}") from error
            if time.monotonic() >= end:
                return

    def request_truth(self):
        """SIM_STATE is in no stream: ask for it at 20 Hz (it comes with ATTITUDE's)."""
        self.command(self.m.MAV_CMD_SET_MESSAGE_INTERVAL, self.m.MAVLINK_MSG_ID_SIM_STATE, 50000)

    @staticmethod
    def mode_name(mode):
        return COPTER_MODES.get(mode, str(mode))

    def _event(self, kind, text):
        self.events.append((self.now(), kind, text))

    def _ekf_flags_now(self, flags, names):
        """The estimator's flags; each change an "ekf" event of the flags going on (+) and off (-)."""
        if self.ekf_flags is not None and flags != self.ekf_flags:
            changed = flags ^ self.ekf_flags
            words = [("+" if flags & bit else "-") + name for bit, name in names.items() if changed & bit]
            if words:
                self._event("ekf", " ".join(words))
        self.ekf_flags = flags

    def _record(self, msg):
        kind = msg.get_type()
        t = self.now()
        if kind == "HEARTBEAT":
            if msg.get_srcComponent() != 1 or msg.type == self.m.MAV_TYPE_GCS:
                return
            armed = bool(msg.base_mode & self.m.MAV_MODE_FLAG_SAFETY_ARMED)
            if armed != self.armed:
                self._event("armed" if armed else "disarmed", "")
            self.armed = armed
            if msg.custom_mode != self.mode:
                self._event("mode", self.mode_name(msg.custom_mode))
            self.mode = msg.custom_mode
        elif kind == "STATUSTEXT":
            self.statustexts.append((t, msg.severity, msg.text))
            self._event("text", msg.text)
        elif kind == "ATTITUDE":
            self.attitude_boot_ms = msg.time_boot_ms
        elif kind == "SIM_STATE":
            if self.attitude_boot_ms is not None and msg.lat_int != 0:
                self.truth.append((self.attitude_boot_ms, msg.lat_int * 1e-7, msg.lon_int * 1e-7, msg.alt))
        elif kind == "GLOBAL_POSITION_INT":
            self.position = msg
            self.ekf.append((msg.time_boot_ms, msg.lat * 1e-7, msg.lon * 1e-7, msg.alt * 1e-3))
        elif kind == "LOCAL_POSITION_NED":
            self.local = msg
        elif kind == "GPS_RAW_INT":
            if self.gps is None or msg.fix_type != self.gps.fix_type:
                self._event("gps_fix", f"fix_type {msg.fix_type}, {msg.satellites_visible} satellites")
            self.gps = msg
            if msg.fix_type >= 3:
                self.gps_track.append((self.boot_ms(), msg.lat * 1e-7, msg.lon * 1e-7, msg.alt * 1e-3))
        elif kind == "EKF_STATUS_REPORT":
            self._ekf_flags_now(msg.flags, EKF_FLAG_NAMES)
        elif kind == "SYS_STATUS":
            self.sys_status = msg
        elif kind == "COMMAND_ACK":
            self.acks.append((t, msg.command, msg.result))
        elif kind == "PARAM_VALUE":
            self.params[msg.param_id] = msg.param_value

    # ---- state questions
    def ekf_good(self):
        return (self.ekf_flags is not None and (self.ekf_flags & EKF_NAV_GOOD) == EKF_NAV_GOOD
                and not self.ekf_flags & (EKF_GPS_GLITCHING | EKF_CONST_POS_MODE))

    def gps_3d(self):
        return self.gps is not None and self.gps.fix_type >= 3

    def prearm_ok(self):
        return self.sys_status is not None and bool(
            self.sys_status.onboard_control_sensors_health & SENSOR_PREARM_CHECK)

    def gps_healthy(self):
        return self.sys_status is not None and bool(self.sys_status.onboard_control_sensors_health & SENSOR_GPS)

    def relative_alt_m(self):
        return self.position.relative_alt * 1e-3 if self.position else 0.0

    def wait(self, predicate, timeout_s, what):
        """Pump until predicate() holds; returns the seconds it took, or None after timeout_s."""
        start = time.monotonic()
        while time.monotonic() - start < timeout_s:
            self.pump(0.05)
            if predicate():
                return time.monotonic() - start
        return None

    # ---- commands
    def command(self, command, *params):
        p = list(params) + [0.0] * (7 - len(params))
        self.mav.command_long_send(self.target_system, 1, command, 0, *p)

    def set_param(self, name, value):
        self.mav.param_set_send(self.target_system, 1, name.encode(), float(value),
                                self.m.MAV_PARAM_TYPE_REAL32)

    def set_mode(self, mode, timeout_s=10.0):
        for _ in range(int(timeout_s)):
            self.command(self.m.MAV_CMD_DO_SET_MODE, self.m.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)
            if self.wait(lambda: self.mode == mode, 1.0, "mode") is not None:
                return True
        return False

    def arm(self, timeout_s=30.0):
        """Arms; returns (seconds, attempts) or (None, attempts)."""
        start = time.monotonic()
        attempts = 0
        while time.monotonic() - start < timeout_s:
            attempts += 1
            self.command(self.m.MAV_CMD_COMPONENT_ARM_DISARM, 1)
            if self.wait(lambda: self.armed, 2.0, "armed") is not None:
                return time.monotonic() - start, attempts
        return None, attempts

    def takeoff(self, alt_m, timeout_s=40.0):
        self.command(self.m.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt_m)
        return self.wait(lambda: self.relative_alt_m() >= alt_m - 0.5, timeout_s, "takeoff") is not None

    def go_local(self, north_m, east_m, down_m):
        """A GUIDED position target, metres North/East/Down of the EKF origin."""
        type_mask = 0b110111111000  # position only
        self.mav.set_position_target_local_ned_send(0, self.target_system, 1, self.m.MAV_FRAME_LOCAL_NED,
                                                    type_mask, north_m, east_m, down_m, 0, 0, 0, 0, 0, 0, 0, 0)

    def fly_to(self, north_m, east_m, down_m, timeout_s=60.0, within_m=1.5):
        self.go_local(north_m, east_m, down_m)

        def arrived():
            if self.local is None:
                return False
            return math.dist((self.local.x, self.local.y, self.local.z), (north_m, east_m, down_m)) < within_m
        return self.wait(arrived, timeout_s, "waypoint") is not None
