"""The pairs' TDOA sets held against the truth: what share of them are the talkers' direct paths, and
the same sets with some of their parts replaced by exact TDOAs, to see what each failing costs.

A talking talker's direct path in a frame is the TDOA of its true position (`truth.jsonl`) at the
frame's stamp, for the talkers whose spurt (`scene.json`) covers the stamp. A reported TDOA is that
direct path when it is within HIT_SAMPLES of it, *near* it when it is within NEAR_SAMPLES (an echo's
or a sidelobe's peak beside it), and *far* otherwise.
"""

import json

import numpy as np

RATE = 16_000
HIT_SAMPLES = 1.5
NEAR_SAMPLES = 8.0
# What the exact sets are announced with: almost always detected, almost no clutter.
EXACT_DETECTION_PROBABILITY = 0.95
EXACT_CLUTTER_RATE = 0.1

MODES = {
    "front-end": "the agents' own sets (the default)",
    "exact": "every talking talker's exact TDOA in every frame, nothing else",
    "hits": "only the agent's TDOAs that are a talking talker's direct path, with the p_D it announced",
    "exact-with-clutter": "every talking talker's exact TDOA, plus the agent's far TDOAs, with its descriptors",
    "without-near": "the agent's TDOAs less those near a direct path (echoes, sidelobes), with its descriptors",
    "near-as-direct": "the agent's TDOAs with each near one moved onto its direct path, with its descriptors",
}


class DirectPaths:
    """The talking talkers' direct-path TDOAs of a scene, by pair and stamp."""

    def __init__(self, scene):
        with open(f"{scene}/scene.json") as f:
            meta = json.load(f)
        with open(f"{scene}/truth.jsonl") as f:
            self.truth = [json.loads(line)["truth"] for line in f]
        self.start = meta["start"]
        self.spurts = meta["spurts"]
        self.stamps = np.array([t["stamp"] for t in self.truth])

    def talking(self, stamp):
        """Whether someone talks at `stamp`."""
        t = stamp - self.start
        return any(a <= t < b for spurts in self.spurts for a, b in spurts)

    def objects_at(self, stamp):
        """The truth's objects of the truth set nearest to `stamp`."""
        return self.truth[int(np.argmin(np.abs(self.stamps - stamp)))]["objects"]

    def tdoas(self, mics, speed_of_sound, stamp):
        """The direct-path TDOA, in seconds, of each talker talking at `stamp` (protocol sign)."""
        t = stamp - self.start
        objects = self.objects_at(stamp)
        m1, m2 = np.array(mics)
        out = []
        for talker, spurts in enumerate(self.spurts):
            if any(a <= t < b for a, b in spurts):
                p = np.array(objects[talker]["position"])
                out.append(float((np.linalg.norm(p - m2) - np.linalg.norm(p - m1)) / speed_of_sound))
        return out


def classify(tdoa, directs):
    """'hit', 'near' or 'far': where `tdoa` lies from the nearest of `directs` (seconds)."""
    gap = min((abs(tdoa - d) * RATE for d in directs), default=np.inf)
    return "hit" if gap < HIT_SAMPLES else "near" if gap < NEAR_SAMPLES else "far"


def peak_shares(paths, outputs):
    """Over the frames in which someone talks: TDOAs per frame, the share of (talker, frame) pairs whose
    direct path is among the TDOAs, and near and far TDOAs per frame."""
    frames = talker_frames = found = 0
    kinds = {"hit": 0, "near": 0, "far": 0}
    for lines in outputs:
        model = next(line["descriptor"]["model"] for line in lines if "descriptor" in line)
        for line in lines:
            if "measurements" not in line or not paths.talking(line["measurements"]["stamp"]):
                continue
            sent = [z[0] for z in line["measurements"]["measurements"]]
            directs = paths.tdoas(model["mics"], model["speed_of_sound"], line["measurements"]["stamp"])
            frames += 1
            talker_frames += len(directs)
            found += sum(any(abs(z - d) * RATE < HIT_SAMPLES for z in sent) for d in directs)
            for z in sent:
                kinds[classify(z, directs)] += 1
    frames = max(frames, 1)
    return {
        "tdoas_per_frame": sum(kinds.values()) / frames,
        "direct_path_found": found / max(talker_frames, 1),
        "near_per_frame": kinds["near"] / frames,
        "far_per_frame": kinds["far"] / frames,
    }


def substituted(paths, outputs, mode):
    """Each agent's lines with its TDOA sets replaced as `mode` says (see MODES)."""
    if mode == "front-end":
        return outputs
    return [substituted_agent(paths, lines, mode) for lines in outputs]


def substituted_agent(paths, lines, mode):
    """One agent's lines with its sets replaced as `mode` says, its descriptors as `announced` says."""
    model = next(line["descriptor"]["model"] for line in lines if "descriptor" in line)
    out = []
    for line in lines:
        if "descriptor" in line:
            out.append({"descriptor": announced(line["descriptor"], mode)})
            continue
        sets = dict(line["measurements"])
        sent = [z[0] for z in sets["measurements"]]
        directs = paths.tdoas(model["mics"], model["speed_of_sound"], sets["stamp"])
        if mode == "exact":
            kept = directs
        elif mode == "hits":
            kept = [z for z in sent if classify(z, directs) == "hit"]
        elif mode == "without-near":
            kept = [z for z in sent if classify(z, directs) != "near"]
        elif mode == "near-as-direct":
            kept = near_moved_onto_direct(sent, directs)
        else:
            kept = directs + [z for z in sent if classify(z, directs) == "far"]
        sets["measurements"] = [[z] for z in kept]
        sets["covariances"] = None
        out.append({"measurements": sets})
    return out


def near_moved_onto_direct(sent, directs):
    """`sent` with each near TDOA replaced by the direct path it is near, one TDOA per direct path: what a
    model that knew which peaks are a talker's echo copies could make of them."""
    kept = []
    for z in sent:
        if classify(z, directs) == "near":
            z = min(directs, key=lambda d: abs(z - d))
        if all(abs(z - k) * RATE >= HIT_SAMPLES for k in kept):
            kept.append(z)
    return kept


def announced(descriptor, mode):
    """The descriptor the substituted sets are sent with."""
    descriptor = dict(descriptor)
    if mode == "exact":
        descriptor["detection_probability"] = EXACT_DETECTION_PROBABILITY
    if mode in ("exact", "hits"):
        descriptor["clutter_rate"] = EXACT_CLUTTER_RATE
    return descriptor
