"""The ground station's link to a PX4 SITL vehicle: the same recording as vehicle.Vehicle (which
talks to ArduPilot), over PX4's UDP ground-station port, with what differs in PX4: its modes (a
main and a sub mode in HEARTBEAT's custom_mode), its estimator's flags (ESTIMATOR_STATUS), the
truth from HIL_STATE_QUATERNION (SIH's ground truth) and the commands a PX4 mission takes
(NAV_TAKEOFF to an altitude above sea level, DO_REPOSITION, NAV_LAND).

The MAVLink messages come from pymavlink's generator run on the PX4 checkout's own message
definitions (common.xml of its mavlink submodule); this file holds no MAVLink definitions.
"""

import math
import socket

import vehicle as V

# PX4's custom_mode: main mode in bits 16-23, sub mode in bits 24-31 (px4_custom_mode.h).
MAIN_AUTO = 4
AUTO_LOITER, AUTO_TAKEOFF, AUTO_LAND = 3, 2, 6
MAIN_NAMES = {1: "MANUAL", 2: "ALTCTL", 3: "POSCTL", 4: "AUTO", 5: "ACRO", 6: "OFFBOARD", 7: "STABILIZED"}
AUTO_NAMES = {1: "READY", 2: "TAKEOFF", 3: "LOITER", 4: "MISSION", 5: "RTL", 6: "LAND", 8: "FOLLOW", 9: "PRECLAND"}

# ESTIMATOR_STATUS flags (MAVLink ESTIMATOR_STATUS_FLAGS).
ESTIMATOR_FLAG_NAMES = {1: "attitude", 2: "vel_horiz", 4: "vel_vert", 8: "pos_horiz_rel", 16: "pos_horiz_abs",
                        32: "pos_vert_abs", 64: "pos_vert_agl", 128: "const_pos_mode", 256: "pred_pos_horiz_rel",
                        512: "pred_pos_horiz_abs", 1024: "gps_glitching", 2048: "accel_error"}
ESTIMATOR_GPS_GLITCH = 1024

GCS_PORT = 14550  # PX4 SITL's ground-station link sends here (px4-rc.mavlink: -u 18570 + instance)


def custom_mode(main, sub=0):
    return (main << 16) | (sub << 24)


def mode_name(mode):
    main, sub = (mode >> 16) & 0xFF, (mode >> 24) & 0xFF
    name = MAIN_NAMES.get(main, str(main))
    return f"{name}.{AUTO_NAMES.get(sub, sub)}" if main == MAIN_AUTO else name


class UdpLink:
    """A UDP socket on PX4's ground-station port, talking to instance's MAVLink (18570 + instance).
    Until PX4 listens, what is sent is refused (ICMP port unreachable): dropped, as on a radio."""

    def __init__(self, instance):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            self.sock.bind(("127.0.0.1", GCS_PORT))
        except OSError as error:
            self.sock.close()
            raise RuntimeError(f"UDP port {GCS_PORT} (PX4's ground-station port) is in use: {error}") from error
        self.sock.connect(("127.0.0.1", 18570 + instance))

    def setblocking(self, flag):
        self.sock.setblocking(flag)

    def sendall(self, data):
        try:
            self.sock.send(data)
        except ConnectionRefusedError:
            pass

    def recv(self, size):
        try:
            return self.sock.recv(size)
        except ConnectionRefusedError as error:  # the refusal of an earlier send: nothing to read
            raise BlockingIOError from error

    def close(self):
        self.sock.close()


class Px4Vehicle(V.Vehicle):
    HOLD = custom_mode(MAIN_AUTO, AUTO_LOITER)

    def __init__(self, mavlink_module, instance):
        super().__init__(mavlink_module, None, None, sock=UdpLink(instance))

    @staticmethod
    def mode_name(mode):
        return mode_name(mode)

    def request_truth(self):
        """SIH's ground truth (HIL_STATE_QUATERNION) on the ground station's link at 20 Hz."""
        self.command(self.m.MAV_CMD_SET_MESSAGE_INTERVAL, self.m.MAVLINK_MSG_ID_HIL_STATE_QUATERNION, 50000)

    def _record(self, msg):
        kind = msg.get_type()
        if kind == "HIL_STATE_QUATERNION":
            # Its time_usec is 0 in this PX4's stream (the ground truth attitude's timestamp, unset
            # under SIH): timed, as ArduPilot's SIM_STATE, by the latest ATTITUDE (50 Hz, same link).
            boot_ms = msg.time_usec // 1000 if msg.time_usec else self.attitude_boot_ms
            if msg.lat != 0 and boot_ms is not None:
                self.truth.append((boot_ms, msg.lat * 1e-7, msg.lon * 1e-7, msg.alt * 1e-3))
        elif kind == "ESTIMATOR_STATUS":  # PX4's flags, in ekf_flags with their own names
            self._ekf_flags_now(msg.flags, ESTIMATOR_FLAG_NAMES)
        else:
            super()._record(msg)

    def ekf_good(self):
        """Navigating: the position flags and no GPS glitch. Not const_pos_mode: PX4's EKF2 sets it
        whenever the vehicle is at rest (ekf_helper.cpp), so on the ground before take-off."""
        f = self.ekf_flags
        return f is not None and (f & V.EKF_NAV_GOOD) == V.EKF_NAV_GOOD and not f & ESTIMATOR_GPS_GLITCH

    def set_mode(self, mode, timeout_s=10.0):
        main, sub = (mode >> 16) & 0xFF, (mode >> 24) & 0xFF
        for _ in range(int(timeout_s)):
            self.command(self.m.MAV_CMD_DO_SET_MODE, self.m.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, main, sub)
            if self.wait(lambda: self.mode == mode, 1.0, "mode") is not None:
                return True
        return False

    def amsl_m(self):
        return self.position.alt * 1e-3 if self.position else 0.0

    def takeoff(self, alt_m, timeout_s=40.0):
        """NAV_TAKEOFF to alt_m above where the vehicle stands (PX4 takes an altitude above sea level)."""
        target = self.amsl_m() - self.relative_alt_m() + alt_m
        nan = float("nan")
        self.command(self.m.MAV_CMD_NAV_TAKEOFF, -1, 0, 0, nan, nan, nan, target)
        return self.wait(lambda: self.relative_alt_m() >= alt_m - 0.5, timeout_s, "takeoff") is not None

    def reposition(self, lat_deg, lon_deg, amsl_m):
        """DO_REPOSITION (as COMMAND_INT: latitude and longitude to 1e-7 degree) in Hold mode."""
        self.mav.command_int_send(self.target_system, 1, self.m.MAV_FRAME_GLOBAL, self.m.MAV_CMD_DO_REPOSITION,
                                  0, 0, -1, self.m.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, 0, float("nan"),
                                  int(round(lat_deg * 1e7)), int(round(lon_deg * 1e7)), amsl_m)

    def fly_to_global(self, lat_deg, lon_deg, amsl_m, timeout_s=90.0, within_m=1.5):
        """Repositions and waits until the estimate is within within_m of the point (re-sent every 5 s)."""
        def arrived():
            if self.position is None:
                return False
            north_m, east_m = V.metres_between(self.position.lat * 1e-7, self.position.lon * 1e-7, lat_deg, lon_deg)
            return math.hypot(north_m, east_m, self.amsl_m() - amsl_m) < within_m
        waited = 0.0
        while waited < timeout_s:
            self.reposition(lat_deg, lon_deg, amsl_m)
            if self.wait(arrived, min(5.0, timeout_s - waited), "waypoint") is not None:
                return True
            waited += 5.0
        return False

    def land(self, timeout_s=90.0):
        nan = float("nan")
        self.command(self.m.MAV_CMD_NAV_LAND, 0, 0, 0, nan, nan, nan, nan)
        return self.wait(lambda: not self.armed, timeout_s, "landed") is not None
