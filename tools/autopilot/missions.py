"""The scripted missions of the autopilot loop over MAVLink: wait until the vehicle is armable, arm
in GUIDED, take off, fly a square, land; and a hover during which gpsemu's control socket injects
faults one after another, each watched until the vehicle has recovered and is back on station."""

import json
import subprocess

import vehicle as V
from flight_stats import errors, record_errors, summary

ALT_M = 10.0
SIDE_M = 100.0

# The faults of the hover: (name, `gpsemu ctl` words, seconds the fault lasts).
FAULTS = [
    ("jump 50 m east", ["jump", "--east", "50", "--duration", "20"], 20),
    ("outage 20 s", ["outage", "--duration", "20"], 20),
    # Strong enough to leave 3 satellites whatever the sky of the hour (a fixed 25 dB left 7 at some hours).
    ("jam leaving 3 satellites", ["jam", "--leave", "3", "--ramp", "5", "--duration", "30"], 30),
    ("spoof drag 2 m/s east", ["spoof", "--speed", "2", "--bearing", "90", "--duration", "30"], 30),
]


def _texts_since(v, t0):
    return [text for t, _, text in v.statustexts if t >= t0]


def wait_armable(v, result, timeout_s=180.0):
    """Until GPS 3-D fix, EKF navigating and the pre-arm checks pass; records when each came."""
    start = v.now()
    checks = {"gps_3d": v.gps_3d, "ekf_good": v.ekf_good, "prearm_ok": v.prearm_ok}
    seen = {}
    while v.now() - start < timeout_s and len(seen) < len(checks):
        v.pump(0.1)
        for name, check in checks.items():
            if name not in seen and check():
                seen[name] = round(v.now() - start, 1)
    result.update({f"{k}_s": seen.get(k) for k in checks})
    result["gps_detected"] = next((t for _, _, t in v.statustexts if "detected" in t), None)
    result["gps_version"] = next((t for _, _, t in v.statustexts if " HW: " in t or "u-blox" in t and "SW" in t),
                                 None)
    if v.gps:
        result["satellites"] = v.gps.satellites_visible
        result["fix_type"] = v.gps.fix_type
    return len(seen) == len(checks)


def arm_and_takeoff(v, result):
    if not v.set_mode(V.GUIDED):
        result["failure"] = "GUIDED refused"
        return False
    t_arm = v.now()
    took, attempts = v.arm()
    result["arm_attempts"] = attempts
    result["prearm_texts"] = sorted(set(t for t in _texts_since(v, t_arm) if "PreArm" in t or "Arm:" in t))
    if took is None:
        result["failure"] = "did not arm"
        return False
    result["armed"] = True
    if not v.takeoff(ALT_M):
        result["failure"] = "takeoff did not reach 10 m"
        return False
    return True


def land(v, timeout_s=90.0):
    v.set_mode(V.LAND)
    return v.wait(lambda: not v.armed, timeout_s, "landed") is not None


def fly_square(v, result):
    """The fault-free flight; result gets the checks and the error against the truth."""
    result["armable"] = wait_armable(v, result)
    if not result["armable"]:
        result["failure"] = "not armable in 180 s"
        return result
    start_ms = v.boot_ms()
    t_start = v.now()
    if not arm_and_takeoff(v, result):
        return result
    x0, y0, z_hover = v.local.x, v.local.y, v.local.z
    corners = [(x0, y0 + SIDE_M), (x0 + SIDE_M, y0 + SIDE_M), (x0 + SIDE_M, y0), (x0, y0)]
    result["corners_reached"] = sum(v.fly_to(n, e, z_hover, 90.0) for n, e in corners)
    result["landed"] = land(v)
    record_errors(v, result, start_ms, v.boot_ms())
    result["flight_s"] = round(v.now() - t_start, 1)
    result["glitch_texts"] = [t for t in _texts_since(v, t_start) if "Glitch" in t or "EKF" in t and "fail" in t.lower()]
    result["glitch_flag_events"] = [e for t, k, e in v.events if t >= t_start and k == "ekf" and "gps_glitching" in e]
    return result



def ctl(gpsemu, path, words):
    """One request on gpsemu's control socket through `gpsemu ctl`; returns its JSON answer."""
    out = subprocess.run([gpsemu, "ctl", path] + words, capture_output=True, text=True, timeout=10)
    try:
        return json.loads(out.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return {"class": "ERROR", "message": (out.stdout + out.stderr).strip()}


def _distance_m(lat1, lon1, lat2, lon2):
    north_m, east_m = V.metres_between(lat1, lon1, lat2, lon2)
    return (north_m ** 2 + east_m ** 2) ** 0.5


def ekf_error_now_m(v):
    """The EKF's latest horizontal error against the truth at its time (None without both)."""
    if not v.ekf or len(v.truth) < 2:
        return None
    horizontal, _ = errors(v.truth[-100:], v.ekf[-1:], 0, 2 ** 62)
    return horizontal[0] if horizontal else None


def _recover(v, station, station_truth, until_s):
    """After a fault: wait until GPS 1 has a 3-D fix and the EKF is healthy and right again (within
    3 m of the truth), then get the vehicle back flying on station (re-arm and take off when a
    failsafe landed it) until the truth is within 3 m of where it hovered before the fault.
    Returns (recovered_t, on_station_t), None for what did not happen by until_s."""
    recovered = None
    while v.now() < until_s:
        v.pump(0.1)
        error_m = ekf_error_now_m(v)
        if recovered is None:
            if v.gps_3d() and v.ekf_good() and error_m is not None and error_m < 3.0:
                recovered = v.now()
            continue
        if not v.armed:
            if v.prearm_ok() and v.set_mode(V.GUIDED) and v.arm(10.0)[0] is not None:
                v.takeoff(ALT_M)
            continue
        if v.mode != V.GUIDED and not v.set_mode(V.GUIDED):
            continue
        v.go_local(*station)
        if v.truth and _distance_m(station_truth[1], station_truth[2], v.truth[-1][1], v.truth[-1][2]) < 3.0 \
                and abs(v.relative_alt_m() - ALT_M) < 1.5:
            return recovered, v.now()
    return recovered, None


def fault_session(v, gpsemu, ctl_path, result, faults=FAULTS):
    """Hover at 10 m and inject each fault; result["faults"] lists each one's reaction."""
    result["armable"] = wait_armable(v, result)
    if not result["armable"] or not arm_and_takeoff(v, result):
        result.setdefault("failure", "not armable")
        return result
    station = (v.local.x, v.local.y, v.local.z)
    v.fly_to(*station, timeout_s=30.0)
    v.pump(3.0)
    station_truth = v.truth[-1]
    result["faults"] = []
    for name, words, duration_s in faults:
        v.fly_to(*station, timeout_s=30.0)
        v.pump(5.0)  # settle
        t0 = v.now()
        ms0 = v.boot_ms()
        answer = ctl(gpsemu, ctl_path, words)
        fault = {"fault": name, "request": "gpsemu ctl " + " ".join(words), "answer": answer.get("class"),
                 "describe": answer.get("describe", answer.get("message"))}
        status = ctl(gpsemu, ctl_path, ["status"])
        fault["status_after_request"] = [f.get("describe", "") + (" (pending)" if f.get("pending") else "")
                                         for r in status.get("receivers", []) for f in r.get("faults", [])]
        min_sats, min_fix = 99, 9
        while v.now() < t0 + duration_s:
            v.pump(0.1)
            if v.gps:
                min_sats = min(min_sats, v.gps.satellites_visible)
                min_fix = min(min_fix, v.gps.fix_type)
        recovered, on_station = _recover(v, station, station_truth, t0 + duration_s + 90.0)
        end_ms = v.boot_ms()
        horizontal, _ = errors(v.truth, v.ekf, ms0, end_ms)
        max_drag_m = max((_distance_m(station_truth[1], station_truth[2], lat, lon)
                          for ms, lat, lon, _ in v.truth if ms0 <= ms <= end_ms), default=0.0)
        fault.update({
            "satellites_min": min_sats, "fix_type_min": min_fix,
            "vehicle_moved_m": round(max_drag_m, 1),
            "ekf_h_error_max_m": summary(horizontal)[1],
            "recovered_s": None if recovered is None else round(recovered - t0, 1),
            "on_station_s": None if on_station is None else round(on_station - t0, 1),
            "events": [(round(t - t0, 1), k, e) for t, k, e in v.events if t0 <= t <= v.now()],
        })
        result["faults"].append(fault)
        if on_station is None:
            result["failure"] = f"not back on station after {name}"
            break
    result["landed"] = land(v)
    return result
