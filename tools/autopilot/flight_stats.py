"""Position error of an autopilot's estimate against the simulator's truth, both from one MAVLink
stream: truth samples (boot_ms, lat, lon, alt_m) from SIM_STATE, estimates from GLOBAL_POSITION_INT
(or GPS_RAW_INT), each estimate compared with the truth interpolated at its own boot time."""

import bisect
import json
import pathlib
import statistics

from vehicle import metres_between


def truth_at(truth, boot_ms):
    """The truth (lat, lon, alt_m) linearly interpolated at boot_ms; None outside the samples or
    across a gap of more than half a second."""
    times = [s[0] for s in truth]
    i = bisect.bisect_left(times, boot_ms)
    if i == 0 or i >= len(truth):
        return None
    a, b = truth[i - 1], truth[i]
    if b[0] - a[0] > 500:
        return None
    f = (boot_ms - a[0]) / (b[0] - a[0]) if b[0] != a[0] else 0.0
    return tuple(a[k] + f * (b[k] - a[k]) for k in (1, 2, 3))


def errors(truth, estimates, start_ms, end_ms):
    """([horizontal_m], [vertical_m]) of the estimates within [start_ms, end_ms]; vertical is
    estimate minus truth (positive: the estimate is above the vehicle)."""
    truth = sorted(set(truth))
    horizontal, vertical = [], []
    for boot_ms, lat, lon, alt_m in estimates:
        if not start_ms <= boot_ms <= end_ms:
            continue
        t = truth_at(truth, boot_ms)
        if t is None:
            continue
        north_m, east_m = metres_between(t[0], t[1], lat, lon)
        horizontal.append((north_m ** 2 + east_m ** 2) ** 0.5)
        vertical.append(alt_m - t[2])
    return horizontal, vertical


def summary(values, absolute=True):
    """(median, max) of |values|, or (None, None) when there are none."""
    if not values:
        return None, None
    mags = [abs(v) for v in values] if absolute else values
    return statistics.median(mags), max(mags)


def fmt(value, digits=2):
    return "-" if value is None else f"{value:.{digits}f}"


EKF_ERROR_FLOOR_M = 0.25  # the error checks allow twice the baseline's or the baseline's + this (metres)


def record_errors(v, result, start_ms, end_ms):
    """The EKF's and GPS 1's error against the truth between start_ms and end_ms, into result."""
    horizontal, vertical = errors(v.truth, v.ekf, start_ms, end_ms)
    result["ekf_h_median_m"], result["ekf_h_max_m"] = summary(horizontal)
    result["ekf_v_median_m"], result["ekf_v_max_m"] = summary(vertical)
    gh, gv = errors(v.truth, v.gps_track, start_ms, end_ms)
    result["gps_h_median_m"], result["gps_h_max_m"] = summary(gh)
    result["gps_v_median_m"], result["gps_v_max_m"] = summary(gv)
    result["samples"] = len(horizontal)


def error_checks(name, r, base, axes=("h", "v")):
    """[(passed, text)]: the EKF's error (median and max) at most twice the baseline flight's or the
    baseline's + EKF_ERROR_FLOOR_M, whichever is larger (a baseline of centimetres would make
    millimetres of flight-to-flight scatter a failure)."""
    if not base or base.get("ekf_h_max_m") is None:
        return [(False, f"{name}: no baseline flight to compare with")]
    out = []
    for axis in axes:
        for stat in ("median", "max"):
            key = f"ekf_{axis}_{stat}_m"
            ours, limit = r.get(key), max(2 * base[key], base[key] + EKF_ERROR_FLOOR_M)
            out.append((ours is not None and ours <= limit,
                        f"{name}: EKF {'horizontal' if axis == 'h' else 'vertical'} error {stat} "
                        f"{fmt(ours)} m <= max(2 x baseline, baseline + {EKF_ERROR_FLOOR_M} m) = {fmt(limit)} m"))
    return out


def print_flight_table(results, skip=()):
    print("\n| flight | GPS 1 | 3-D fix | EKF good | armable | arm attempts | EKF error horizontal median / max (m) "
          "| vertical median / max (m) | GPS error horizontal median / max (m) | glitch |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, r in results.items():
        if name in skip:
            continue
        print(f"| {name} | {r['gps']} | {r.get('gps_3d_s')} s | {r.get('ekf_good_s')} s | {r.get('prearm_ok_s')} s "
              f"| {r.get('arm_attempts')} | {fmt(r.get('ekf_h_median_m'))} / {fmt(r.get('ekf_h_max_m'))} "
              f"| {fmt(r.get('ekf_v_median_m'))} / {fmt(r.get('ekf_v_max_m'))} "
              f"| {fmt(r.get('gps_h_median_m'))} / {fmt(r.get('gps_h_max_m'))} "
              f"| {'yes' if r.get('glitch_texts') or r.get('glitch_flag_events') else 'no'} |")


def report(results, results_checks, work):
    """Prints the checks, writes work/results.json; the tool's exit status (0 all pass, 1 not)."""
    for passed, text in results_checks:
        print(f"{'PASS' if passed else 'FAIL'} {text}")
    (pathlib.Path(work) / "results.json").write_text(json.dumps(results, indent=1, default=str))
    failed = sum(1 for passed, _ in results_checks if not passed)
    print(f"\n{len(results_checks) - failed} of {len(results_checks)} checks pass; logs in {work}")
    return 1 if failed or not results_checks else 0


def add_common_args(p, flights, gpsemu_default, noise_help, jobs_help):
    """The options both autopilot loops take (after the autopilot's own checkout option)."""
    p.add_argument("--flights", default=",".join(flights), metavar="LIST",
                   help=f"which flights, in order (default {','.join(flights)})")
    p.add_argument("--gpsemu", default=gpsemu_default, metavar="PATH",
                   help="the gpsemu binary (default: this checkout's build)")
    p.add_argument("--gpsemu-arg", action="append", default=[], metavar="ARG",
                   help="one more argument for every gpsemu (repeatable), e.g. --gpsemu-arg=--width=1")
    p.add_argument("--noise", default="none", metavar="MODEL", help=noise_help)
    p.add_argument("--jobs", type=int, default=2, help=jobs_help)
    p.add_argument("--work", metavar="DIR", help="keep logs here (default: a new directory in $TMPDIR)")


def parse_common(p, argv, flights):
    args = p.parse_args(argv)
    unknown = [f for f in args.flights.split(",") if f not in flights]
    if unknown:
        p.error(f"--flights: unknown {', '.join(unknown)} (known: {', '.join(flights)})")
    return args


def save_flight(result, rig, work, name, summary_keys):
    """The end of a flight: gpsemu's summary lines (those holding one of summary_keys) into the
    result, written to work/name/result.json, and the one-line outcome printed."""
    if rig.gpsemu:
        log = rig.gpsemu_log.read_text(errors="replace").splitlines()
        result["gpsemu_summary"] = [line for line in log if any(k in line for k in summary_keys)][-20:]
    (pathlib.Path(work) / name / "result.json").write_text(json.dumps(result, indent=1, default=str))
    print(f"    {result.get('failure', 'flown')}", flush=True)
    return result
