"""Runs a scene of make_scene.py through the real chain and scores it.

Each pair's WAV goes through `edge-agent mic-pair --wav` (with the descriptor it was given, which the
agent refines from its own output), the sets and the truth are merged in stamp order into a replay
file, and `fusion-server replay` runs it with the scene's `server.toml`. The score: mean OSPA(x, y)
(c = 1 m, p = 1) and the share of track sets with the right count, over the track sets after 6 s
stamped while someone talks.

Each scene's line also gives the agents' TDOAs held against the truth. With `--tdoas MODE` the agents'
sets are replaced in part by the truth's exact TDOAs before the replay (`tdoa_truth.MODES`), which shows
what each of the front end's failings costs.

    python3 score_scene.py SCENE [SCENE ...] [--bin target/release] [--frontend-config FILE] [--tdoas MODE]
"""

import argparse
import json
import os
import subprocess
import tempfile

import numpy as np
from scipy.optimize import linear_sum_assignment

import tdoa_truth

PAIRS = ["mics_s", "mics_e", "mics_n", "mics_w"]
SETTLED_S = 6.0


def arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--bin", default="target/release", help="directory of edge-agent and fusion-server")
    parser.add_argument("--frontend-config", help="mic front-end TOML given to every agent")
    parser.add_argument("--tdoas", choices=tdoa_truth.MODES, default="front-end",
                        help="; ".join(f"{k}: {v}" for k, v in tdoa_truth.MODES.items()))
    return parser.parse_args()


def agent_lines(args, scene, start, work):
    """Each pair's agent output, one list of lines per pair."""
    outputs = []
    for name in PAIRS:
        output = f"{work}/{name}.jsonl"
        command = [f"{args.bin}/edge-agent", "mic-pair", "--wav", f"{scene}/{name}.wav",
                   "--descriptor", f"{scene}/{name}.json", "--start", str(start), "--output", output]
        if args.frontend_config:
            command += ["--frontend-config", args.frontend_config]
        subprocess.run(command, check=True, env=dict(os.environ, RUST_LOG="error"))
        with open(output) as f:
            outputs.append([json.loads(line) for line in f])
    return outputs


def stamp_of(line):
    return next(iter(line.values())).get("stamp", -1.0)


def merged(truth_lines, agent_outputs):
    """The truth and each agent's lines in stamp order, as `fusion-checker` merges them: a line without a
    stamp (a descriptor) keeps its place before its agent's next set, so that a descriptor the agent
    refined part-way through applies from there on, as it would live."""
    keyed = [(stamp_of(line), 0, 0, 0, line) for line in truth_lines]
    for pair, lines in enumerate(agent_outputs):
        next_stamp = float("inf")
        for index in range(len(lines) - 1, -1, -1):
            if "measurements" in lines[index]:
                next_stamp = lines[index]["measurements"]["stamp"]
            keyed.append((next_stamp, 1, pair, index, lines[index]))
    keyed.sort(key=lambda key: key[:4])
    return [line for *_, line in keyed]


def ospa(truth, tracks):
    """OSPA with c = 1 m, p = 1 between two point sets in the plane."""
    m, n = len(truth), len(tracks)
    if max(m, n) == 0:
        return 0.0
    if min(m, n) == 0:
        return 1.0
    d = np.minimum(np.linalg.norm(truth[:, None] - tracks[None], axis=2), 1.0)
    rows, cols = linear_sum_assignment(d)
    return (d[rows, cols].sum() + abs(m - n)) / max(m, n)


def score(scene_dir, tracks_path):
    """Mean OSPA(x, y), share of right counts and number of the track sets after SETTLED_S stamped while
    someone talks."""
    paths = tdoa_truth.DirectPaths(scene_dir)
    total, right, n = 0.0, 0, 0
    with open(tracks_path) as f:
        for line in f:
            track_set = json.loads(line)
            stamp = track_set["stamp"]
            if stamp - paths.start < SETTLED_S or not paths.talking(stamp):
                continue
            x = np.array([o["position"][:2] for o in paths.objects_at(stamp)]).reshape(-1, 2)
            y = np.array([o["position"][:2] for o in track_set["tracks"]]).reshape(-1, 2)
            total += ospa(x, y)
            right += len(x) == len(y)
            n += 1
    return total / max(n, 1), right / max(n, 1), n


def run(args, scene):
    """The scene's figures: its mean OSPA(x, y), share of right counts and number of track sets scored,
    and the agents' TDOAs held against the truth (`tdoa_truth.peak_shares`)."""
    with open(f"{scene}/scene.json") as f:
        start = json.load(f)["start"]
    with open(f"{scene}/truth.jsonl") as f:
        truth_lines = [json.loads(line) for line in f]
    paths = tdoa_truth.DirectPaths(scene)
    with tempfile.TemporaryDirectory() as work:
        outputs = agent_lines(args, scene, start, work)
        shares = tdoa_truth.peak_shares(paths, outputs)
        lines = merged(truth_lines, tdoa_truth.substituted(paths, outputs, args.tdoas))
        return (*replayed(args, scene, work, lines), shares)


def replayed(args, scene, work, lines):
    """`fusion-server replay` of `lines` with the scene's configuration, scored."""
    with open(f"{work}/replay.jsonl", "w") as f:
        f.writelines(json.dumps(l) + "\n" for l in lines)
    subprocess.run([f"{args.bin}/fusion-server", "replay", "--config", f"{scene}/server.toml",
                    "--input", f"{work}/replay.jsonl", "--output", f"{work}/tracks.jsonl"],
                   check=True, capture_output=True, env=dict(os.environ, RUST_LOG="error"))
    return score(scene, f"{work}/tracks.jsonl")


def main():
    args = arguments()
    figures = []
    for scene in args.scenes:
        ospa_xy, right, n, shares = run(args, scene)
        figures.append((ospa_xy, right, *shares.values()))
        print(f"{scene}: {n} track sets while someone talks: mean OSPA(x, y) {ospa_xy:.3f} m, "
              f"count right {100 * right:.1f} %; {describe(shares)}")
    if len(figures) > 1:
        mean = np.mean(figures, axis=0)
        print(f"mean over {len(figures)} scenes: OSPA(x, y) {mean[0]:.3f} m, count right {100 * mean[1]:.1f} %; "
              f"{describe(dict(zip(shares, mean[2:])))}")


def describe(shares):
    """The agents' TDOAs against the truth, in words."""
    return (f"the agents sent {shares['tdoas_per_frame']:.2f} TDOAs a frame, a talking talker's direct path "
            f"among them {100 * shares['direct_path_found']:.0f} % of the time, {shares['near_per_frame']:.2f} "
            f"near one and {shares['far_per_frame']:.2f} far from all")


if __name__ == "__main__":
    main()
