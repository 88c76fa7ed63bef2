#!/usr/bin/python3
"""Parses every sentence of a gpsemu NMEA file with python3-nmea2 (pynmea2), checksum checking on,
and checks that the sentences of each epoch agree with each other. Run by core_clients_tools_test.

Usage: pynmea2_check.py [--ubx] FILE
Prints one JSON line (counts per type, epochs, epochs with a fix); exits 1 with the reasons on
any failure. An epoch starts at each RMC (u-blox order: RMC VTG GGA GSA GSV... GLL GST ZDA).
With --ubx the file is a --protocol nmea+ubx stream: UBX frames between the sentences are taken
out first (each frame's checksum checked, counted by class and id in "ubx"), and each NAV-PVT
must carry the time of the RMC after it (a u-blox writes an epoch's NAV messages before its NMEA).
"""
import json
import struct
import sys

import pynmea2


def fail(problems):
    for p in problems[:20]:
        print(p, file=sys.stderr)
    print(f"{len(problems)} problems", file=sys.stderr)
    sys.exit(1)


def gsv_satellites(msg):
    """PRNs of one GSV: 4 fields per satellite after the 3 header fields; an odd trailing field is
    the NMEA 4.1 signal ID (pynmea2 1.15 does not know it, so read the raw fields)."""
    body = msg.data[3:]
    if len(body) % 4 == 1:
        body = body[:-1]
    if len(body) % 4 != 0:
        raise ValueError(f"GSV with {len(msg.data)} fields")
    return [int(body[i]) for i in range(0, len(body), 4)]


def check_epoch(index, epoch, problems):
    by_type = {}
    for msg in epoch:
        by_type.setdefault(msg.sentence_type, []).append(msg)
    rmc = by_type.get("RMC", [None])[0]
    gga = by_type.get("GGA", [None])[0]
    gll = by_type.get("GLL", [None])[0]
    where = f"epoch {index} ({rmc.timestamp if rmc else '?'})"
    # One time for the whole epoch.
    times = {m.timestamp for t in ("RMC", "GGA", "GLL", "GST", "ZDA") for m in by_type.get(t, [])}
    if len(times) > 1:
        problems.append(f"{where}: several times {times}")
    has_fix = gga.gps_qual > 0 if gga else (rmc.status == "A" if rmc else False)
    if rmc and (rmc.status == "A") != has_fix:
        problems.append(f"{where}: RMC status {rmc.status} but GGA quality {gga.gps_qual}")
    if has_fix:
        positions = [(round(m.latitude, 9), round(m.longitude, 9)) for m in (rmc, gga, gll) if m]
        if len(set(positions)) != 1:
            problems.append(f"{where}: positions differ {positions}")
    else:
        for m in (rmc, gga, gll):
            if m and (m.lat or m.lon):
                problems.append(f"{where}: position in a no-fix {m.sentence_type}")
    if "ZDA" in by_type and rmc and rmc.datestamp:  # a cold receiver has no date yet
        zda = by_type["ZDA"][0]
        if (zda.day, zda.month, zda.year) != (rmc.datestamp.day, rmc.datestamp.month, rmc.datestamp.year):
            problems.append(f"{where}: ZDA date differs from RMC")
    in_view = []
    if "GSV" in by_type:
        # One group per system (talker) and signal: numbered 1..total, its count in each sentence.
        ranges = {"GP": (1, 64), "GL": (65, 96), "GA": (1, 36), "GB": (1, 63), "GQ": (1, 10)}
        groups = []
        for m in by_type["GSV"]:
            if int(m.msg_num) == 1:
                groups.append([])
            if not groups:
                problems.append(f"{where}: GSV group without its first sentence")
                groups.append([])
            groups[-1].append(m)
        for gsv in groups:
            total = int(gsv[0].num_messages)
            if [int(m.msg_num) for m in gsv] != list(range(1, total + 1)):
                problems.append(f"{where}: GSV messages {[m.msg_num for m in gsv]} of {total}")
            ids = []
            for m in gsv:
                ids += gsv_satellites(m)
            if len(ids) != int(gsv[0].num_sv_in_view):
                problems.append(f"{where}: GSV lists {len(ids)} satellites, says {gsv[0].num_sv_in_view}")
            low, high = ranges.get(gsv[0].talker, (1, 99))
            if len(set(ids)) != len(ids) or any(not low <= p <= high for p in ids):
                problems.append(f"{where}: {gsv[0].talker}GSV IDs {ids}")
            in_view += ids
        for m in by_type["GSV"]:
            body = m.data[3:]
            for i in range(0, len(body) - len(body) % 4, 4):
                el, az, snr = body[i + 1], body[i + 2], body[i + 3]
                if not (0 <= int(el) <= 90 and 0 <= int(az) < 360 and (snr == "" or 0 <= int(snr) <= 99)):
                    problems.append(f"{where}: implausible satellite {body[i:i + 4]}")
    if "GSA" in by_type:
        used = [int(getattr(m, f"sv_id{k:02}")) for m in by_type["GSA"] for k in range(1, 13)
                if getattr(m, f"sv_id{k:02}")]
        fix_type = by_type["GSA"][0].mode_fix_type
        if (fix_type != "1") != has_fix:
            problems.append(f"{where}: GSA fix type {fix_type}")
        if gga and has_fix and len(used) != int(gga.num_sats):
            problems.append(f"{where}: GSA lists {len(used)} used, GGA says {gga.num_sats}")
        if in_view and not set(used) <= set(in_view):
            problems.append(f"{where}: used {used} not all in view {in_view}")
        if has_fix and gga and abs(float(by_type["GSA"][0].hdop) - float(gga.horizontal_dil)) > 0.005:
            problems.append(f"{where}: GSA HDOP differs from GGA")
    if "GST" in by_type and has_fix:
        gst = by_type["GST"][0]
        if not (gst.std_dev_latitude > 0 and gst.std_dev_longitude > 0 and gst.rms > 0):
            problems.append(f"{where}: GST without error estimates")
    return has_fix


def split_ubx(data, problems):
    """The NMEA text of a mixed stream, the UBX frames' counts by "class-id", and the UTC times
    (hhmmss.ss) of the NAV-PVTs each followed by the first RMC after it."""
    text, counts, pvt_then_rmc = bytearray(), {}, []
    pending_pvt = None
    i = 0
    while i < len(data):
        if data[i:i + 2] == b"\xb5\x62":
            if i + 8 > len(data):
                problems.append(f"byte {i}: truncated UBX header")
                break
            length = struct.unpack_from("<H", data, i + 4)[0]
            body = data[i + 2:i + 6 + length]
            a = b = 0
            for byte in body:
                a = (a + byte) & 0xFF
                b = (b + a) & 0xFF
            if data[i + 6 + length:i + 8 + length] != bytes([a, b]):
                problems.append(f"byte {i}: UBX frame with a bad checksum")
            key = f"{data[i + 2]:02x}-{data[i + 3]:02x}"
            counts[key] = counts.get(key, 0) + 1
            if key == "01-07" and length == 92:
                hour, minute, second = data[i + 14], data[i + 15], data[i + 16]
                nano = struct.unpack_from("<i", data, i + 22)[0]
                pending_pvt = f"{hour:02}{minute:02}{second:02}.{round(nano / 1e7):02}"
            i += 8 + length
        elif data[i:i + 1] == b"$":
            end = data.find(b"\r\n", i)
            if end < 0:
                problems.append(f"byte {i}: sentence without CR LF")
                break
            line = data[i:end + 2]
            if line[3:6] == b"RMC" and pending_pvt is not None:
                pvt_then_rmc.append((pending_pvt, line.split(b",")[1].decode("ascii")))
                pending_pvt = None
            text += line
            i = end + 2
        else:
            problems.append(f"byte {i}: neither a UBX frame nor a sentence")
            break
    for pvt, rmc in pvt_then_rmc:
        if rmc and pvt != rmc:  # an empty RMC time: a cold receiver that does not know the time yet
            problems.append(f"NAV-PVT at {pvt} followed by the RMC of {rmc}")
    return bytes(text), counts, len(pvt_then_rmc)


def main():
    args = sys.argv[1:]
    mixed = args[0] == "--ubx"
    data = open(args[-1], "rb").read()
    problems = []
    ubx_counts, pvt_before_rmc = {}, 0
    if mixed:
        data, ubx_counts, pvt_before_rmc = split_ubx(data, problems)
    lines = data.split(b"\r\n")
    if lines[-1] != b"":
        fail(["file does not end in CR LF"])
    counts = {}
    epochs = []
    for number, raw in enumerate(lines[:-1], 1):
        line = raw.decode("ascii")
        if len(line) + 2 > 82:
            problems.append(f"line {number}: {len(line) + 2} characters: {line}")
        try:
            msg = pynmea2.parse(line, check=True)
        except pynmea2.ParseError as e:
            problems.append(f"line {number}: {type(e).__name__}: {e}")
            continue
        counts[msg.sentence_type] = counts.get(msg.sentence_type, 0) + 1
        if msg.sentence_type == "RMC" or not epochs:
            epochs.append([])
        epochs[-1].append(msg)
    # Checksum checking is really on: a corrupted checksum must be refused.
    sample = lines[0].decode("ascii")
    corrupted = sample[:-2] + ("00" if sample[-2:] != "00" else "01")
    try:
        pynmea2.parse(corrupted, check=True)
        problems.append("pynmea2 accepted a corrupted checksum")
    except pynmea2.ChecksumError:
        pass
    fixes = sum(check_epoch(i, e, problems) for i, e in enumerate(epochs))
    if problems:
        fail(problems)
    summary = {"counts": counts, "epochs": len(epochs), "fix_epochs": fixes}
    if mixed:
        summary.update({"ubx": ubx_counts, "pvt_before_rmc": pvt_before_rmc})
    print(json.dumps(summary, sort_keys=True))


if __name__ == "__main__":
    main()
