#!/usr/bin/env python3
"""Reads what `fusion-checker` printed (JSON on stdin) and answers one question for tests/compose/run.sh.

  status-sensor NAME   -> "alive received processed late invalid lost" of one sensor (or "missing")
  status-sensors       -> one line per sensor: "name alive received processed late invalid lost"
  status-rejected      -> "undecodable unknown_sensor invalid late" server-wide rejection counters
  apart-windows MIN_DIST MIN_LEN
                       -> reads replay lines (edge-agent sim --truth --output -) and prints "start end" (scenario
                          seconds) of every stretch of at least MIN_LEN s in which all people stay at least
                          MIN_DIST m apart (horizontally)
  ids-compare BEFORE AFTER
                       -> compares two `fusion-checker ids` outputs (files): for every true object seen in
                          both, is its most frequent track id the same? Prints one line per object and
                          exits 1 when an id changed or fewer than MIN_OBJECTS objects could be compared.
  view-scene           -> reads fusion-view's /api/scene JSON and prints "tracks sensors alive_sensors site truth"
                          (truth: the people of the simulation's truth in the scene)
  sniff                -> reads `fusion-checker sniff` and prints "forged forged_status genuine_victim genuine_tracks
                          status_replies" (VICTIM, default lidar: genuine sets of that sensor seen)
  impostor             -> reads `fusion-checker impersonate` and prints "puts queries_answered"
  role                 -> reads `fusion-checker status --instance ID` and prints "role lost" (its "role", or
                          "none"; the sum of its sensors' lost counters)
  sites                -> reads `fusion-checker sites` and prints "site:tracks:alive" per site, sorted
  gaps                 -> reads `fusion-checker gaps` and prints "sets max_gap_s"

Only the standard library: CI machines have a plain Python 3.
"""

import json
import math
import sys

MIN_OBJECTS = 2


def load_json(text):
    # The checker prints nothing but the JSON document on stdout; tolerate stray lines around it.
    start = min(i for i in (text.find("{"), text.find("[")) if i >= 0)
    return json.loads(text[start:])


def sensor_line(sensor):
    fields = ("received", "processed", "late", "invalid", "lost")
    alive = "true" if sensor["alive"] else "false"
    return " ".join([alive] + [str(sensor[f]) for f in fields])


def dominant_ids(ids):
    """{object id: track id seen most often}."""
    return {obj: max(tracks.items(), key=lambda kv: kv[1])[0] for obj, tracks in ids.items() if tracks}


def apart_windows(lines, min_dist, min_len):
    """Stretches of scenario time in which every pair of people is at least min_dist apart."""
    windows, start, last = [], None, None
    for line in lines:
        record = json.loads(line)
        if "truth" not in record:
            continue
        truth = record["truth"]
        points = [o["position"][:2] for o in truth["objects"]]
        closest = min(
            (math.dist(a, b) for i, a in enumerate(points) for b in points[i + 1:]),
            default=float("inf"),
        )
        if closest >= min_dist and start is None:
            start = truth["stamp"]
        elif closest < min_dist and start is not None:
            windows.append((start, truth["stamp"]))
            start = None
        last = truth["stamp"]
    if start is not None:
        windows.append((start, last))
    return [(a, b) for a, b in windows if b - a >= min_len]


def probe_line(command, doc, args):
    """One line of figures from the checker's probes (impostor, sniffer, instance status, sites)."""
    if command == "sniff":
        victim = args[0] if args else "lidar"
        genuine = doc["genuine"]
        tracks = sum(n for key, n in genuine.items() if key.endswith("/tracks"))
        figures = (sum(doc["forged"].values()), doc["forged_status_replies"],
                   genuine.get(f"{victim}/measurements", 0), tracks, doc["status_replies"])
        return " ".join(str(f) for f in figures)
    if command == "impostor":
        return f"{sum(doc['puts'].values())} {doc['queries_answered']}"
    if command == "role":
        lost = sum(s.get("lost", 0) for s in doc.get("sensors", []))
        return f"{doc.get('role') or 'none'} {lost}"
    if command == "gaps":
        return f"{doc['sets']} {doc['max_gap_s']:.2f}"
    sites = sorted(set(doc["tracks"]) | set(doc["status"]))
    return " ".join(f"{s}:{doc['tracks'].get(s, 0)}:{doc['status'].get(s, 0)}" for s in sites)


def main(argv):
    command = argv[1]
    if command == "apart-windows":
        for start, end in apart_windows(sys.stdin, float(argv[2]), float(argv[3])):
            print(f"{start:.1f} {end:.1f}")
        return 0
    if command == "ids-compare":
        with open(argv[2]) as f:
            before = dominant_ids(load_json(f.read()))
        with open(argv[3]) as f:
            after = dominant_ids(load_json(f.read()))
        common = sorted(set(before) & set(after), key=int)
        same = 0
        for obj in common:
            verdict = "same" if before[obj] == after[obj] else "CHANGED"
            same += before[obj] == after[obj]
            print(f"person {obj}: track id {before[obj]} before, {after[obj]} after ({verdict})")
        print(f"{same} of {len(common)} people kept their track id")
        return 0 if common and same == len(common) and len(common) >= MIN_OBJECTS else 1
    if command == "view-scene":
        scene = load_json(sys.stdin.read())
        alive = sum(1 for s in scene["sensors"] if s["alive"])
        truth = scene.get("truth")
        people = len(truth) if isinstance(truth, list) else "-"
        print(len(scene["tracks"]), len(scene["sensors"]), alive, scene["site"] or "-", people)
        return 0
    if command in ("sniff", "impostor", "role", "sites", "gaps"):
        print(probe_line(command, load_json(sys.stdin.read()), argv[2:]))
        return 0
    status = load_json(sys.stdin.read())
    if command == "status-sensor":
        match = [s for s in status["sensors"] if s["sensor"] == argv[2]]
        print(sensor_line(match[0]) if match else "missing")
    elif command == "status-sensors":
        for s in status["sensors"]:
            print(s["sensor"], sensor_line(s))
    elif command == "status-rejected":
        r = status["rejected"]
        print(r["undecodable"], r["unknown_sensor"], r["invalid"], r["late"])
    else:
        print(f"unknown command {command}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
