"""Validates a hairsys cache's Foxglove view against the official foxglove.SceneUpdate schema.

Usage: python3 validate_foxglove.py CACHE.mcap MAX_STRANDS

Every message on /hairsys/scene must validate (jsonschema) against the schema stored in the file,
whose name must be foxglove.SceneUpdate with encoding jsonschema; there must be one per frame, at
the frame's log_time, and its line strips must be the shown strands' points of that frame.
Exit 0 on success, 1 on a mismatch, 2 if a package is missing (pip install mcap jsonschema).
"""
import json
import struct
import sys

try:
    import jsonschema
    from mcap.reader import make_reader
except ImportError as e:
    print(f"missing Python package ({e}); run: pip install mcap jsonschema", file=sys.stderr)
    sys.exit(2)


def fail(msg):
    print(f"validate_foxglove: {msg}", file=sys.stderr)
    sys.exit(1)


def main(path, max_strands):
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        layout = next(a for a in reader.iter_attachments() if a.name == "hairsys/layout.bin").data
        strands, points = struct.unpack_from("<II", layout, 0)
        offsets = struct.unpack_from(f"<{strands + 1}I", layout, 8)
        shown = min(max_strands, strands)
        chosen = [i * strands // shown for i in range(shown)]
        views = [c for c in summary.channels.values() if c.topic == "/hairsys/scene"]
        if len(views) != 1:
            fail(f"{len(views)} view channels")
        view = views[0]
        schema_record = summary.schemas[view.schema_id]
        if schema_record.name != "foxglove.SceneUpdate" or schema_record.encoding != "jsonschema":
            fail(f"schema {schema_record.name} / {schema_record.encoding}")
        if view.message_encoding != "json":
            fail(f"message encoding {view.message_encoding}")
        schema = json.loads(schema_record.data)
        validator = jsonschema.Draft202012Validator(schema)
        frames, updates = {}, {}
        f.seek(0)
        for _schema, channel, message in make_reader(f).iter_messages():
            if channel.topic == "/hairsys/frames":
                x = struct.unpack_from(f"<{3 * points}f", message.data, 20)
                frames[message.log_time] = x
            elif channel.topic == "/hairsys/scene":
                doc = json.loads(message.data)
                errors = list(validator.iter_errors(doc))
                if errors:
                    fail(f"message at {message.log_time} ns does not validate: {errors[0].message}")
                updates[message.log_time] = doc
        if set(frames) != set(updates):
            fail(f"{len(frames)} frames but {len(updates)} scene updates at other times")
        for t, doc in updates.items():
            entity = doc["entities"][0]
            stamp = entity["timestamp"]["sec"] * 1_000_000_000 + entity["timestamp"]["nsec"]
            if stamp != t:
                fail(f"entity timestamp {stamp} != log_time {t}")
            lines = entity["lines"]
            if len(lines) != shown:
                fail(f"{len(lines)} lines, expected {shown}")
            for line, s in zip(lines, chosen):
                pts = [(p["x"], p["y"], p["z"]) for p in line["points"]]
                want = [frames[t][3 * i: 3 * i + 3] for i in range(offsets[s], offsets[s + 1])]
                if len(pts) != len(want) or any(abs(a - b) > 1e-6 for p, q in zip(pts, want) for a, b in zip(p, q)):
                    fail(f"strand {s} at {t} ns does not match the cached frame")
    print(f"{len(updates)} scene updates valid, {shown} strands each")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
