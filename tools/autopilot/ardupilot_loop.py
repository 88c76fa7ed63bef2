#!/usr/bin/env python3
"""tools/autopilot-loop ardupilot --ardupilot DIR: ArduCopter SITL flying on gpsemu
(docs/autopilots.md#ardupilot-sitl).

The SITL vehicle's own GPS is off; its GPS port (SERIAL3) is gpsemu's pty; gpsemu takes the
vehicle's true state from SITL's SIM_STATE on a second MAVLink port (--source mavlink:tcp:...).
A scripted mission flies the same square with SITL's own GPS (the baseline) and with gpsemu
(u-blox M8N from its factory state; NMEA), and a hover takes gpsemu's faults one by one. Prints
what ArduPilot did and the checks; exit 0 when they pass, 1 when one fails, 2 when the set-up fails.
"""

import argparse
import os
import pathlib
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import missions  # noqa: E402
import sitl  # noqa: E402
from flight_stats import (add_common_args, error_checks, fmt, parse_common, print_flight_table, report,  # noqa: E402
                          save_flight)
from vehicle import Vehicle  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The flights: (name, what drives GPS 1, gpsemu arguments or None for SITL's own GPS, mission,
# ArduPilot parameters of the flight). ArduPilot's GPS1_TYPE 1 (auto) detects u-blox, SBP, SiRF
# and ERB receivers but not NMEA: an NMEA receiver needs GPS1_TYPE 5. ArduPilot takes an NMEA
# receiver's data for 200 ms old (GPS1_DELAY_MS 0: the backend's default lag); gpsemu's NMEA is
# written that late (--latency 0.2) so the EKF's lag matches, as a user sets GPS1_DELAY_MS to a
# receiver's measured latency (with gpsemu's default 50 ms the error is 0.56 m median, 1.5 m at most).

FLIGHTS = {
    "sitl-gps": ("SITL's simulated u-blox (baseline)", None, "square", []),
    "ubx": ("gpsemu u-blox M8N, factory state", ["--receiver", "ublox-m8n"], "square", []),
    "faults": ("gpsemu u-blox M8N, faults in a hover", ["--receiver", "ublox-m8n"], "faults", []),
    "nmea": ("gpsemu NMEA only, 5 Hz, 200 ms latency (GPS1_TYPE 5)",
             ["--protocol", "nmea", "--rate", "5", "--latency", "0.2"], "square",
             ["GPS1_TYPE 5"]),
}


def parse_args(argv):
    p = argparse.ArgumentParser(prog="tools/autopilot-loop ardupilot", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ardupilot", required=True, metavar="DIR",
                   help="an ArduPilot checkout with its submodules; ArduCopter SITL is built there if needed")
    add_common_args(p, FLIGHTS, str(ROOT / "build/emulator/gpsemu"),
                    "gpsemu's noise model (default none: SITL's own GPS has no noise either)",
                    "waf -j when SITL must be built (default 2)")
    return parse_common(p, argv, FLIGHTS)


def run_flight(name, args, binary, mav):
    title, gpsemu_args, mission, params = FLIGHTS[name]
    result = {"flight": name, "gps": title}
    if gpsemu_args is not None:
        gpsemu_args = gpsemu_args + ["--noise", args.noise] + args.gpsemu_arg
        result["gpsemu_args"] = " ".join(gpsemu_args)
    print(f"--- {name}: {title}", flush=True)
    rig = sitl.Rig(binary, args.ardupilot, args.work, name, args.gpsemu, gpsemu_args, params)
    try:
        v = Vehicle(mav, "127.0.0.1", rig.mavlink_port)
        if mission == "square":
            missions.fly_square(v, result)
        else:
            missions.fault_session(v, args.gpsemu, rig.ctl, result)
        result["texts"] = [f"{t:.1f} {text}" for t, _, text in v.statustexts]
        result["version"] = next((text for _, _, text in v.statustexts if text.startswith("ArduCopter")), None)
    except RuntimeError as error:
        result["failure"] = str(error)
    finally:
        result["gpsemu_exit"] = rig.stop()
    return save_flight(result, rig, args.work, name,
                       ("pose input", "epochs emitted", "client input", "fault ", "error", "warning"))


def checks(results):
    """[(passed, text)]: the pass criteria of docs/autopilots.md."""
    out = []
    base = results.get("sitl-gps")
    for name in ("ubx", "nmea"):
        r = results.get(name)
        if not r:
            continue
        out.append((bool(r.get("gps_detected")), f"{name}: GPS detected ({r.get('gps_detected')})"))
        out.append((r.get("gps_3d_s") is not None, f"{name}: 3-D fix after {r.get('gps_3d_s')} s"))
        out.append((r.get("ekf_good_s") is not None and r.get("prearm_ok_s") is not None,
                    f"{name}: EKF healthy after {r.get('ekf_good_s')} s, armable after {r.get('prearm_ok_s')} s"))
        out.append((bool(r.get("armed")), f"{name}: armed in GUIDED ({r.get('arm_attempts')} attempts"
                    + (f"; {'; '.join(r.get('prearm_texts'))}" if r.get("prearm_texts") else "") + ")"))
        out.append((r.get("corners_reached") == 4 and bool(r.get("landed")),
                    f"{name}: square flown ({r.get('corners_reached')} of 4 corners), landed: {r.get('landed')}"))
        out.append((not r.get("glitch_texts") and not r.get("glitch_flag_events"),
                    f"{name}: no GPS glitch in the fault-free flight ({r.get('glitch_texts')})"))
        out += error_checks(name, r, base)
    if base:
        out.append((base.get("corners_reached") == 4 and bool(base.get("landed")),
                    f"sitl-gps: baseline square flown ({base.get('corners_reached')} of 4), landed"))
    f = results.get("faults")
    if f:
        for fault in f.get("faults", []):
            out.append((bool(fault["events"]) and fault["on_station_s"] is not None,
                        f"faults: {fault['fault']}: {len(fault['events'])} reactions listed, recovered after "
                        f"{fault['recovered_s']} s, back on station after {fault['on_station_s']} s"))
        out.append((len(f.get("faults", [])) == len(missions.FAULTS), f"faults: {len(f.get('faults', []))} of "
                    f"{len(missions.FAULTS)} faults run" + (f" ({f['failure']})" if f.get("failure") else "")))
    return out


def print_tables(results):
    print_flight_table(results, skip=("faults",))
    f = results.get("faults")
    if not f:
        return
    print("\n| fault (in a 10 m hover) | ArduPilot's reaction (s after the request) | satellites min | fix min "
          "| vehicle moved (m) | EKF error max (m) | recovered | back on station |")
    print("|---|---|---|---|---|---|---|---|")
    for fault in f.get("faults", []):
        reaction = "; ".join(f"+{t} {k} {e}".strip() for t, k, e in fault["events"][:14])
        print(f"| {fault['fault']} | {reaction} | {fault['satellites_min']} | {fault['fix_type_min']} "
              f"| {fault['vehicle_moved_m']} | {fmt(fault['ekf_h_error_max_m'], 1)} | +{fault['recovered_s']} s "
              f"| +{fault['on_station_s']} s |")


def main(argv):
    args = parse_args(argv)
    args.ardupilot = os.path.abspath(args.ardupilot)
    args.work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="autopilot-loop-"))
    os.makedirs(args.work, exist_ok=True)
    try:
        if not os.access(args.gpsemu, os.X_OK):
            raise sitl.Stop(f"--gpsemu {args.gpsemu}: not built (tools/setup builds it)")
        sitl.check_checkout(args.ardupilot)
        binary = sitl.build(args.ardupilot, args.jobs, os.path.join(args.work, "waf.log"))
        mav = sitl.mavlink_module(args.ardupilot, args.work)
        commit = sitl.commit_of(args.ardupilot)
        print(f"ArduPilot {commit} ({binary}); logs in {args.work}", flush=True)
        results = {}
        for name in args.flights.split(","):
            results[name] = run_flight(name, args, binary, mav)
    except sitl.Stop as error:
        print(f"tools/autopilot-loop: {error}", file=sys.stderr)
        return 2
    version = next((r.get("version") for r in results.values() if r.get("version")), None)
    print(f"\nArduPilot commit {commit}{', ' + version if version else ''}, {time.strftime('%Y-%m-%d')}")
    print_tables(results)
    print()
    return report(results, checks(results), args.work)

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
