#!/usr/bin/env python3
"""Send vehicle poses to gpsemu (--source udp:PORT or tcp:PORT), as an external simulator would.

The example a simulator user copies: one JSON object per UDP datagram, or per '\\n'-terminated
line over TCP, at a fixed rate paced on absolute deadlines (no drift):

    {"t": 12.34, "x": 1.5, "y": -2.0, "z": 0.0, "ve": 1.0, "vn": 0.0, "vu": 0.0}

x, y, z are metres East, North, Up from gpsemu's --origin; with --geodetic the script sends
lat/lon/alt instead (converted from the same local metres about --origin). t is the sender's time
in seconds (here: seconds since the script started); ve/vn/vu the velocity in m/s.

Trajectories:
  circle   a circle of --radius metres about the origin at --speed m/s, counter-clockwise,
           starting at its southern point heading east (like gpsemu's sim:circle)
  line     from the origin along --heading (degrees true) at --speed m/s
  still    stationary at --at X,Y[,Z]
  csv FILE a recorded trajectory, linearly interpolated at --rate. The first line names the
           columns, in any order:
             t            seconds (required, increasing; the file starts at its first t)
             x, y [, z]   metres East, North, Up from the origin, or
             lat, lon [, alt]  degrees, degrees, metres above MSL (sent as lat/lon/alt)
             ve, vn [, vu]     optional velocity, m/s (otherwise gpsemu uses the track)
           e.g.  t,x,y,z
                 0,0,0,0
                 1,1.5,0,0

Examples:
  gpsemu --source udp:5005 --rate 10 --output pty:/tmp/gps &
  tools/send_pose.py circle --to udp:127.0.0.1:5005 --rate 50 --radius 20 --speed 2
  tools/send_pose.py line --to tcp:127.0.0.1:5006 --heading 45 --speed 5 --duration 60
  tools/send_pose.py csv drive.csv --to udp:5005 --rate 100 --loop
"""

import argparse
import csv
import json
import math
import socket
import sys
import time

WGS84_A = 6378137.0
WGS84_E2 = 6.69437999014e-3


def parse_to(text):
    """'udp:HOST:PORT' / 'tcp:PORT' -> (scheme, host, port)."""
    scheme, sep, rest = text.partition(":")
    if not sep or scheme not in ("udp", "tcp"):
        raise argparse.ArgumentTypeError(f"'{text}': expected udp:[HOST:]PORT or tcp:[HOST:]PORT")
    host, _, port = rest.rpartition(":")
    host = host.strip("[]") or "127.0.0.1"
    try:
        return scheme, host, int(port)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}': the port must be a number") from None


def parse_numbers(text, count_min, count_max):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}': expected comma-separated numbers") from None
    if not count_min <= len(values) <= count_max:
        raise argparse.ArgumentTypeError(f"'{text}': expected {count_min} to {count_max} numbers")
    return values


class LocalToGeodetic:
    """Local ENU metres about an origin -> lat/lon/alt, on the WGS84 ellipsoid's local radii.

    Within a few kilometres of the origin this agrees with gpsemu's GeographicLib frame to
    millimetres. The local frame's horizontal plane is tangent at the origin, so a point on it
    d metres away is d^2/2R above the ellipsoid (8 cm at 1 km): that is added to the altitude."""

    def __init__(self, lat_deg, lon_deg, alt_m):
        self.lat0, self.lon0, self.alt0 = lat_deg, lon_deg, alt_m
        s = math.sin(math.radians(lat_deg))
        w = math.sqrt(1.0 - WGS84_E2 * s * s)
        self.r_north = WGS84_A * (1.0 - WGS84_E2) / w**3 + alt_m   # meridian radius (m)
        self.r_east = (WGS84_A / w + alt_m) * math.cos(math.radians(lat_deg))  # parallel radius (m)

    def __call__(self, x, y, z):
        lat = self.lat0 + math.degrees(y / self.r_north)
        lon = self.lon0 + math.degrees(x / self.r_east)
        return lat, lon, self.alt0 + z + (x * x + y * y) / (2.0 * 6371000.0)


def circle(radius, speed):
    w = speed / radius

    def at(t):
        a = w * t
        return (radius * math.sin(a), -radius * math.cos(a), 0.0), (speed * math.cos(a), speed * math.sin(a), 0.0)

    return at


def line(heading_deg, speed):
    h = math.radians(heading_deg)
    ve, vn = speed * math.sin(h), speed * math.cos(h)
    return lambda t: ((ve * t, vn * t, 0.0), (ve, vn, 0.0))


def still(x, y, z):
    return lambda t: ((x, y, z), (0.0, 0.0, 0.0))


def read_csv(path):
    """Returns (times, rows, geodetic, has_velocity): rows of (p1, p2, p3, ve, vn, vu)."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader)]
        col = {name: i for i, name in enumerate(header)}
        known = {"t", "x", "y", "z", "lat", "lon", "alt", "ve", "vn", "vu"}
        unknown = set(col) - known
        if unknown or "t" not in col:
            sys.exit(f"{path}: columns must be t and x,y[,z] or lat,lon[,alt], optionally ve,vn[,vu]; "
                     f"got {header}")
        geodetic = "lat" in col
        p = ("lat", "lon", "alt") if geodetic else ("x", "y", "z")
        if p[0] not in col or p[1] not in col:
            sys.exit(f"{path}: needs both {p[0]} and {p[1]} columns")
        has_velocity = "ve" in col and "vn" in col
        times, rows = [], []
        for number, row in enumerate(reader, start=2):
            if not row or row[0].startswith("#"):
                continue
            try:
                get = lambda name, default=0.0: float(row[col[name]]) if name in col else default
                t = get("t")
                third = get(p[2], math.nan if geodetic else 0.0)
                rows.append((get(p[0]), get(p[1]), third, get("ve"), get("vn"), get("vu")))
            except (ValueError, IndexError):
                sys.exit(f"{path}:{number}: not a row of numbers: {row}")
            if times and t <= times[-1]:
                sys.exit(f"{path}:{number}: t must increase")
            times.append(t)
        if len(times) < 2:
            sys.exit(f"{path}: needs at least two rows")
        return times, rows, geodetic, has_velocity


def csv_trajectory(times, rows, loop):
    span = times[-1] - times[0]
    index = [0]

    def at(t):
        if loop:
            t = math.fmod(t, span)
        t = min(t + times[0], times[-1])
        i = index[0] if times[index[0]] <= t else 0
        while i + 2 < len(times) and times[i + 1] <= t:
            i += 1
        index[0] = i
        f = (t - times[i]) / (times[i + 1] - times[i])
        row = [a + f * (b - a) for a, b in zip(rows[i], rows[i + 1])]
        return tuple(row[:3]), tuple(row[3:])

    return at


class Link:
    """A UDP socket or a TCP connection (reconnecting while gpsemu is not listening)."""

    def __init__(self, scheme, host, port):
        self.scheme, self.address = scheme, (host, port)
        self.sock = None
        self.connect()

    def connect(self):
        family = socket.AF_INET6 if ":" in self.address[0] else socket.AF_INET
        if self.scheme == "udp":
            self.sock = socket.socket(family, socket.SOCK_DGRAM)
            return
        while True:
            try:
                self.sock = socket.create_connection(self.address, timeout=2.0)
                self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                return
            except OSError as e:
                print(f"send_pose: tcp {self.address[0]}:{self.address[1]}: {e}; retrying", file=sys.stderr)
                time.sleep(0.5)

    def send(self, message):
        data = message.encode()
        try:
            if self.scheme == "udp":
                self.sock.sendto(data, self.address)
            else:
                self.sock.sendall(data + b"\n")
        except ConnectionRefusedError:
            pass  # UDP: nobody listening yet; the next datagram may find gpsemu
        except OSError as e:
            if self.scheme == "udp":
                raise
            print(f"send_pose: connection lost ({e}); reconnecting", file=sys.stderr)
            self.sock.close()
            self.connect()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trajectory", choices=["circle", "line", "still", "csv"], help="what to drive")
    ap.add_argument("file", nargs="?", help="csv: the trajectory file")
    ap.add_argument("--to", type=parse_to, default=("udp", "127.0.0.1", 5005), metavar="udp|tcp:[HOST:]PORT",
                    help="where gpsemu listens (default udp:127.0.0.1:5005)")
    ap.add_argument("--rate", type=float, default=50.0, help="poses per second (default 50)")
    ap.add_argument("--duration", type=float, help="stop after this many seconds (default: run until Ctrl-C)")
    ap.add_argument("--speed", type=float, default=2.0, help="circle/line speed, m/s (default 2)")
    ap.add_argument("--radius", type=float, default=20.0, help="circle radius, m (default 20)")
    ap.add_argument("--heading", type=float, default=90.0, help="line heading, degrees true (default 90 = east)")
    ap.add_argument("--at", type=lambda s: parse_numbers(s, 2, 3), default=[0.0, 0.0, 0.0], metavar="X,Y[,Z]",
                    help="still: position, metres East, North, Up of the origin (default 0,0,0)")
    ap.add_argument("--loop", action="store_true", help="csv: start over after the last row")
    ap.add_argument("--geodetic", action="store_true", help="send lat/lon/alt instead of x/y/z (needs --origin)")
    ap.add_argument("--origin", type=lambda s: parse_numbers(s, 3, 3), default=[43.0725, -89.4125, 260.0],
                    metavar="LAT,LON,ALT", help="gpsemu's --origin, for --geodetic (default 43.0725,-89.4125,260)")
    ap.add_argument("--no-velocity", action="store_true", help="leave out ve/vn/vu (gpsemu then uses the track)")
    ap.add_argument("--no-time", action="store_true", help="leave out t")
    args = ap.parse_args()
    if args.rate <= 0 or args.rate > 2000:
        ap.error("--rate must be in (0, 2000] poses per second")

    csv_geodetic = False
    with_velocity = not args.no_velocity
    if args.trajectory == "csv":
        if not args.file:
            ap.error("csv needs a FILE")
        times, rows, csv_geodetic, has_velocity = read_csv(args.file)
        trajectory = csv_trajectory(times, rows, args.loop)
        with_velocity = with_velocity and has_velocity
        if not args.loop and args.duration is None:
            args.duration = times[-1] - times[0]
    elif args.trajectory == "circle":
        trajectory = circle(args.radius, args.speed)
    elif args.trajectory == "line":
        trajectory = line(args.heading, args.speed)
    else:
        trajectory = still(*(args.at + [0.0])[:3])
    to_geodetic = LocalToGeodetic(*args.origin) if args.geodetic else None

    scheme, host, port = args.to
    link = Link(scheme, host, port)
    print(f"send_pose: {args.trajectory} at {args.rate:g} Hz to {scheme}:{host}:{port}", file=sys.stderr)
    period = 1.0 / args.rate
    start = time.monotonic()
    sent = 0
    try:
        while args.duration is None or sent * period <= args.duration:
            deadline = start + sent * period
            delay = deadline - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            t = time.monotonic() - start
            (p1, p2, p3), velocity = trajectory(t)
            message = {} if args.no_time else {"t": round(t, 6)}
            if csv_geodetic:
                message.update(lat=p1, lon=p2)
                if not math.isnan(p3):
                    message["alt"] = p3
            elif to_geodetic:
                lat, lon, alt = to_geodetic(p1, p2, p3)
                message.update(lat=round(lat, 10), lon=round(lon, 10), alt=round(alt, 4))
            else:
                message.update(x=round(p1, 5), y=round(p2, 5), z=round(p3, 5))
            if with_velocity:
                message.update(ve=round(velocity[0], 5), vn=round(velocity[1], 5), vu=round(velocity[2], 5))
            link.send(json.dumps(message, allow_nan=False, separators=(",", ":")))
            sent += 1
    except KeyboardInterrupt:
        pass
    print(f"send_pose: {sent} poses sent", file=sys.stderr)


if __name__ == "__main__":
    main()
