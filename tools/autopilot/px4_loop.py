#!/usr/bin/env python3
"""tools/autopilot-loop px4 --px4 DIR: PX4 SITL (the SIH quadrotor) flying on gpsemu
(docs/autopilots.md#px4-sitl).

SIH, PX4's simulator inside the px4 process, flies the vehicle; its own simulated GPS is off and
PX4's real GPS driver (`gps`, PX4-GPSDrivers) reads gpsemu's pty; gpsemu takes the vehicle's true
state from SIH's HIL_STATE_QUATERNION over UDP. The same square is flown with SIH's simulated GPS
(the baseline), with gpsemu as a u-blox M8N from its factory state (the driver configures it), and
with gpsemu as an NMEA receiver. Prints what PX4 did and the checks; exit 0 when they pass, 1 when
one fails, 2 when the set-up fails.
"""

import argparse
import math
import os
import pathlib
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import px4  # noqa: E402
import px4_vehicle as P  # noqa: E402
from flight_stats import (add_common_args, error_checks, parse_common, print_flight_table, record_errors,  # noqa: E402
                          report, save_flight)
from missions import ALT_M, SIDE_M, wait_armable  # noqa: E402
from sitl import HOME, Stop  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]

# (title, gpsemu arguments or None for SIH's GPS, PX4 gps driver protocol, PX4 parameters)
FLIGHTS = {
    "sih-gps": ("SIH's simulated GPS (baseline)", None, None, []),
    "ubx": ("gpsemu u-blox M8N, factory state (gps -p ubx)", ["--receiver", "ublox-m8n"], "ubx", []),
    # PX4's NMEA driver takes eph/epv from GST only (0 without it): GST added to the default set.
    "nmea": ("gpsemu NMEA only + GST, 5 Hz, 115200 baud (gps -p nmea)",
             ["--protocol", "nmea", "--rate", "5", "--sentences", "RMC,VTG,GGA,GSA,GSV,GLL,GST"], "nmea", []),
}


def parse_args(argv):
    p = argparse.ArgumentParser(prog="tools/autopilot-loop px4", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--px4", required=True, metavar="DIR",
                   help="a PX4-Autopilot checkout with its submodules; PX4 SITL is built there if needed")
    p.add_argument("--config", default="px4_sitl_default", metavar="NAME",
                   help="the PX4 build configuration (default px4_sitl_default; px4_sitl_<variant> for "
                        "boards/px4/sitl/<variant>.px4board)")
    add_common_args(p, FLIGHTS, str(ROOT / "build/emulator/gpsemu"),
                    "gpsemu's noise model (default none: SIH's GPS has its own small noise)",
                    "ninja -j when PX4 must be built (default 2)")
    return parse_common(p, argv, FLIGHTS)


def fly_square(v, result):
    """Hold, arm, take off to 10 m, fly a 100 m square by DO_REPOSITION, land."""
    result["armable"] = wait_armable(v, result)
    if not result["armable"]:
        result["failure"] = "not armable in 180 s"
        return result
    start_ms = v.boot_ms()
    t_start = v.now()
    if not v.set_mode(P.Px4Vehicle.HOLD):
        result["failure"] = "Hold mode refused"
        return result
    took, attempts = v.arm()
    result["arm_attempts"] = attempts
    result["prearm_texts"] = sorted(set(t for tt, _, t in v.statustexts
                                        if tt >= t_start and ("preflight" in t.lower() or "denied" in t.lower())))
    if took is None:
        result["failure"] = "did not arm"
        return result
    result["armed"] = True
    if not v.takeoff(ALT_M):
        result["failure"] = "takeoff did not reach 10 m"
        return result
    lat0, lon0 = v.position.lat * 1e-7, v.position.lon * 1e-7
    amsl = v.amsl_m() - v.relative_alt_m() + ALT_M
    m_per_deg_lat = math.radians(1.0) * 6378137.0  # flat earth over the 100 m square
    m_per_deg_lon = m_per_deg_lat * math.cos(math.radians(lat0))
    corners = [(0.0, SIDE_M), (SIDE_M, SIDE_M), (SIDE_M, 0.0), (0.0, 0.0)]  # (north, east) metres
    result["corners_reached"] = sum(v.fly_to_global(lat0 + n / m_per_deg_lat, lon0 + e / m_per_deg_lon, amsl)
                                    for n, e in corners)
    result["landed"] = v.land()
    record_errors(v, result, start_ms, v.boot_ms())
    result["truth_samples"] = len(v.truth)
    result["flight_s"] = round(v.now() - t_start, 1)
    result["glitch_flag_events"] = [e for t, k, e in v.events if t >= t_start and k == "ekf" and "+gps_glitching" in e]
    result["glitch_texts"] = [t for tt, _, t in v.statustexts if tt >= t_start and "glitch" in t.lower()]
    return result


def run_flight(name, args, build_dir, mav):
    title, gpsemu_args, protocol, params = FLIGHTS[name]
    result = {"flight": name, "gps": title}
    if gpsemu_args is not None:
        gpsemu_args = gpsemu_args + ["--noise", args.noise] + args.gpsemu_arg
        result["gpsemu_args"] = " ".join(gpsemu_args)
    print(f"--- {name}: {title}", flush=True)
    rig = px4.Rig(build_dir, args.work, name, args.gpsemu, gpsemu_args, protocol, params)
    v = None
    try:
        v = P.Px4Vehicle(mav, rig.instance)
        fly_square(v, result)
    except RuntimeError as error:
        result["failure"] = str(error)
    finally:
        if v is not None:
            v.sock.close()
            result["texts"] = [f"{t:.1f} {text}" for t, _, text in v.statustexts][:200]
            result["events"] = [f"{t:.1f} {k} {e}" for t, k, e in v.events][:300]
        result["gpsemu_exit"] = rig.stop()
    result["px4_gps_lines"] = rig.px4_lines("[gps]", "GPS", "gps")[:40]
    result["gps_configured"] = next((line for line in result["px4_gps_lines"] if "configured" in line), None)
    return save_flight(result, rig, args.work, name, ("pose input", "epochs emitted", "client input", "error", "warning"))


def checks(results):
    """[(passed, text)]: the pass criteria of docs/autopilots.md#px4-sitl."""
    out = []
    base = results.get("sih-gps")
    for name in ("ubx", "nmea"):
        r = results.get(name)
        if not r:
            continue
        out.append((bool(r.get("gps_configured")), f"{name}: PX4's gps driver configured the receiver "
                                                    f"({r.get('gps_configured')})"))
        out.append((r.get("gps_3d_s") is not None, f"{name}: 3-D fix after {r.get('gps_3d_s')} s"))
        out.append((r.get("ekf_good_s") is not None and r.get("prearm_ok_s") is not None,
                    f"{name}: estimator navigating after {r.get('ekf_good_s')} s, armable after "
                    f"{r.get('prearm_ok_s')} s"))
        out.append((bool(r.get("armed")), f"{name}: armed ({r.get('arm_attempts')} attempts"
                    + (f"; {'; '.join(r.get('prearm_texts'))}" if r.get("prearm_texts") else "") + ")"))
        out.append((r.get("corners_reached") == 4 and bool(r.get("landed")),
                    f"{name}: square flown ({r.get('corners_reached')} of 4 corners), landed: {r.get('landed')}"))
        out.append((not r.get("glitch_texts") and not r.get("glitch_flag_events"),
                    f"{name}: no GPS glitch ({r.get('glitch_texts')}, {r.get('glitch_flag_events')})"))
        # PX4's NMEA driver marks its NED velocity valid with the vertical part never set (0, as
        # NMEA has none): EKF2 fuses a vertical speed of 0 in the climb and the descent, on any NMEA
        # receiver. The NMEA flight's vertical error is listed, not checked against u-blox's.
        out += error_checks(name, r, base, axes=("h",) if name == "nmea" else ("h", "v"))
    if base:
        out.append((base.get("corners_reached") == 4 and bool(base.get("landed")),
                    f"sih-gps: baseline square flown ({base.get('corners_reached')} of 4), landed"))
    return out


def main(argv):
    args = parse_args(argv)
    args.px4 = os.path.abspath(args.px4)
    args.work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="autopilot-loop-px4-"))
    os.makedirs(args.work, exist_ok=True)
    try:
        if not os.access(args.gpsemu, os.X_OK):
            raise Stop(f"--gpsemu {args.gpsemu}: not built (tools/setup builds it)")
        px4.check_checkout(args.px4)
        build_dir = px4.build(args.px4, args.config, args.jobs, os.path.join(args.work, "build.log"))
        mav = px4.mavlink_module(args.px4, args.work)
        commit = px4.commit_of(args.px4)
        print(f"PX4 {commit} ({build_dir}); home {HOME[0]},{HOME[1]},{HOME[2]}; logs in {args.work}", flush=True)
        results = {}
        for name in args.flights.split(","):
            results[name] = run_flight(name, args, build_dir, mav)
    except Stop as error:
        print(f"tools/autopilot-loop: {error}", file=sys.stderr)
        return 2
    print(f"\nPX4 {commit}, {args.config}, {time.strftime('%Y-%m-%d')}")
    print_flight_table(results)
    print()
    return report(results, checks(results), args.work)

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
