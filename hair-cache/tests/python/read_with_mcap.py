#!/usr/bin/env python3
"""Reads a hairsys cache with Foxglove's official Python MCAP reader (`pip install mcap`).

Usage: python3 read_with_mcap.py FILE.mcap

Checks the summary (statistics, schema, channel, chunk indexes), the `hairsys` metadata record,
the `hairsys/layout.bin` attachment, and every frame message decoded per the layout documented
in hair-cache/src/layout.rs: `hairsys.frame.v1` (f32) or `hairsys.frame.q16.v1` (quantized u16,
decoded as min + q * (max - min) / 65535 in double precision). Exits 0 when everything agrees, 1 with a message otherwise, and 2
when the `mcap` module is missing.
"""

import math
import struct
import sys

try:
    from mcap.reader import make_reader
except ImportError as e:  # pragma: no cover - environment problem
    print(f"the Python `mcap` package is missing ({e}); run `pip install mcap`", file=sys.stderr)
    sys.exit(2)

FRAME_TOPIC = "/hairsys/frames"
FRAME_ENCODING = "hairsys.frame.v1"
FRAME_Q16_ENCODING = "hairsys.frame.q16.v1"
# Schema name of each frame message encoding.
SCHEMA_NAMES = {FRAME_ENCODING: "hairsys.Frame", FRAME_Q16_ENCODING: "hairsys.FrameQ16"}
SCHEMA_ENCODING = "text/plain"
LAYOUT_NAME = "hairsys/layout.bin"


def fail(message):
    print(f"read_with_mcap.py: {message}", file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def frame_time_ns(frame, fps):
    # round(frame / fps * 1e9), half away from zero (values are non-negative).
    return int(math.floor(frame / fps * 1e9 + 0.5))


def decode_layout(data):
    check(len(data) >= 8, f"layout attachment has {len(data)} bytes")
    strands, points = struct.unpack_from("<II", data, 0)
    expected = 8 + 4 * (strands + 1) + 4 * (points - strands) + 4 * points
    check(len(data) == expected, f"layout has {len(data)} bytes, expected {expected}")
    offsets = struct.unpack_from(f"<{strands + 1}I", data, 8)
    check(offsets[0] == 0 and offsets[-1] == points, f"bad offsets {offsets[:3]}..{offsets[-1]}")
    check(all(b > a for a, b in zip(offsets, offsets[1:])), "offsets do not increase")
    pos = 8 + 4 * (strands + 1)
    rest = struct.unpack_from(f"<{points - strands}f", data, pos)
    radii = struct.unpack_from(f"<{points}f", data, pos + 4 * (points - strands))
    check(all(math.isfinite(v) for v in rest + radii), "non-finite rest length or radius")
    return strands, points


def decode_frame(data, points):
    check(len(data) == 20 + 24 * points, f"payload of {len(data)} bytes for {points} points")
    version, frame, time_s, count = struct.unpack_from("<IIdI", data, 0)
    check(version == 1, f"payload format version {version}")
    check(count == points, f"frame {frame} has {count} points, layout {points}")
    values = struct.unpack_from(f"<{6 * points}f", data, 20)
    check(all(math.isfinite(v) for v in values), f"frame {frame} has a non-finite value")
    return frame, time_s


def to_f32(value):
    """The nearest f32 to a Python float."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def decode_frame_q16(data, points):
    """Decodes a quantized payload; returns (frame, time_s, positions, velocities) as flat lists."""
    check(len(data) == 68 + 12 * points, f"quantized payload of {len(data)} bytes for {points} points")
    version, frame, time_s, count = struct.unpack_from("<IIdI", data, 0)
    check(version == 1, f"payload format version {version}")
    check(count == points, f"frame {frame} has {count} points, layout {points}")
    bounds = struct.unpack_from("<12f", data, 20)
    pos_min, pos_max, vel_min, vel_max = bounds[0:3], bounds[3:6], bounds[6:9], bounds[9:12]
    check(all(math.isfinite(b) for b in bounds), f"frame {frame} has non-finite bounds")
    check(all(a <= b for a, b in zip(pos_min + vel_min, pos_max + vel_max)),
          f"frame {frame} has a min above its max")
    q = struct.unpack_from(f"<{6 * points}H", data, 68)

    def values(qs, lo, hi):
        # value = min + q * (max - min) / 65535, in double precision (then rounded to f32).
        return [to_f32(lo[i % 3] + v * (hi[i % 3] - lo[i % 3]) / 65535) for i, v in enumerate(qs)]

    positions = values(q[:3 * points], pos_min, pos_max)
    velocities = values(q[3 * points:], vel_min, vel_max)
    for values_, lo, hi in [(positions, pos_min, pos_max), (velocities, vel_min, vel_max)]:
        for i, v in enumerate(values_):
            check(lo[i % 3] <= v <= hi[i % 3], f"frame {frame} value {i} out of its bounds")
    return frame, time_s, positions, velocities


def main():
    if len(sys.argv) != 2:
        fail("usage: read_with_mcap.py FILE.mcap")
    path = sys.argv[1]
    with open(path, "rb") as f:
        reader = make_reader(f)
        header = reader.get_header()
        check(header.profile == "hairsys", f"profile {header.profile!r}")
        summary = reader.get_summary()
        check(summary is not None, "no summary section")
        stats = summary.statistics
        check(stats is not None, "no statistics record")

        metadata = list(reader.iter_metadata())
        hairsys = [m for m in metadata if m.name == "hairsys"]
        check(len(hairsys) == 1, f"{len(hairsys)} `hairsys` metadata records")
        meta = hairsys[0].metadata
        check(meta.get("format_version") == "1", f"format_version {meta.get('format_version')!r}")
        fps = float(meta["fps"])
        first_frame = int(meta["first_frame"])
        check(fps > 0, f"fps {fps}")

        attachments = [a for a in reader.iter_attachments() if a.name == LAYOUT_NAME]
        check(len(attachments) == 1, f"{len(attachments)} layout attachments")
        strands, points = decode_layout(attachments[0].data)
        check(int(meta["strand_count"]) == strands, "strand_count differs from the layout")
        check(int(meta["point_count"]) == points, "point_count differs from the layout")
        check(stats.attachment_count == 1, f"statistics count {stats.attachment_count} attachments")
        check(stats.metadata_count == 1, f"statistics count {stats.metadata_count} metadata")

        frames = []
        if stats.message_count > 0:
            channels = [c for c in summary.channels.values() if c.topic == FRAME_TOPIC]
            check(len(channels) == 1, f"{len(channels)} frame channels")
            channel = channels[0]
            encoding = channel.message_encoding
            check(encoding in SCHEMA_NAMES, f"encoding {encoding}")
            schema = summary.schemas[channel.schema_id]
            check(schema.name == SCHEMA_NAMES[encoding], f"schema name {schema.name!r}")
            check(schema.encoding == SCHEMA_ENCODING, f"schema encoding {schema.encoding!r}")
            check(b"little-endian" in schema.data, "schema text does not describe the payload")
            check(len(summary.chunk_indexes) == stats.chunk_count, "chunk indexes vs statistics")
            check(len(summary.chunk_indexes) >= 1, "no chunk index")

            for schema, chan, message in reader.iter_messages(topics=[FRAME_TOPIC]):
                if encoding == FRAME_Q16_ENCODING:
                    frame, time_s, _, _ = decode_frame_q16(message.data, points)
                else:
                    frame, time_s = decode_frame(message.data, points)
                check(message.sequence == frame, f"sequence {message.sequence} for frame {frame}")
                check(time_s == frame / fps, f"frame {frame} time {time_s}")
                expected_ns = frame_time_ns(frame, fps)
                check(message.log_time == expected_ns, f"frame {frame} log_time {message.log_time}")
                check(message.publish_time == expected_ns, f"frame {frame} publish_time")
                frames.append(frame)
            check(stats.channel_message_counts.get(channel.id) == len(frames),
                  "statistics per-channel message count")
            check(stats.message_start_time == frame_time_ns(frames[0], fps), "message_start_time")
            check(stats.message_end_time == frame_time_ns(frames[-1], fps), "message_end_time")

        check(stats.message_count == len(frames),
              f"statistics count {stats.message_count} messages, read {len(frames)}")
        check(all(b > a for a, b in zip(frames, frames[1:])), "frames do not increase")
        check(all(f >= first_frame for f in frames), "a frame precedes first_frame")
    kind = " (quantized)" if frames and encoding == FRAME_Q16_ENCODING else ""
    print(f"{path}: {len(frames)} frames{kind} of {points} points in {strands} strands: ok")


if __name__ == "__main__":
    main()
