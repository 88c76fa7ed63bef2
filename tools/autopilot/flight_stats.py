"""Position error of an autopilot's estimate against the simulator's truth, both from one MAVLink
stream: truth samples (boot_ms, lat, lon, alt_m) from SIM_STATE, estimates from GLOBAL_POSITION_INT
(or GPS_RAW_INT), each estimate compared with the truth interpolated at its own boot time."""

import bisect
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
