"""Stone Soup's GM-PHD on Vo & Ma's linear demo, on the data of gmphd/tests/exp_vo_demo.rs.

Reads the JSON written by `cargo run --release -p gmphd --example vo_demo_export -- FILE`
(the test's own truth and measurement sets, 50 seeded runs x 100 steps), runs Stone
Soup's GM-PHD on every scan and scores it like the Rust tests: Vo & Ma's extraction
(every component of weight > 0.5 gives round(w) copies of its position), OSPA with
c = 100 m, p = 1 on positions, per step; mean over all runs x steps.

The filter is built exactly as in Stone Soup's own GM-PHD tutorial
(docs/tutorials/filters/GMPHDTutorial.py of v1.9.1): KalmanPredictor + KalmanUpdater,
DistanceHypothesiser(Mahalanobis, missed_distance) inside a GaussianMixtureHypothesiser
(order_by_detection=True), PHDUpdater, GaussianMixtureReducer; each step the birth
components are added to the mixture with the scan's timestamp, then hypothesise
(this predicts every component to the scan time), update, reduce.

Gating: the tutorial's `missed_distance=3` on the DistanceHypothesiser drops every
component-measurement pair whose Mahalanobis distance in measurement space is >= 3
(chi^2 with 2 dof: 98.9 % of true detections kept). That is Stone Soup's gating here
(no separate Gater in the tutorial). --ungated uses missed_distance=inf (every pair,
the exact Vo & Ma update); --gate-distance D sets another gate, e.g. 4.292 = our
filter's 99.99 % chi^2 gate.

Usage: python vo_linear.py DATA.json [--runs N] [--gated | --ungated] [--gate-distance D]
"""

import argparse
import json
import math
import statistics
import time
from datetime import datetime, timedelta

import numpy as np
from scipy.optimize import linear_sum_assignment

from stonesoup.hypothesiser.distance import DistanceHypothesiser
from stonesoup.hypothesiser.gaussianmixture import GaussianMixtureHypothesiser
from stonesoup.measures import Mahalanobis
from stonesoup.mixturereducer.gaussianmixture import GaussianMixtureReducer
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.transition.linear import (
    CombinedLinearGaussianTransitionModel, ConstantVelocity)
from stonesoup.predictor.kalman import KalmanPredictor
from stonesoup.types.detection import Detection
from stonesoup.types.state import TaggedWeightedGaussianState
from stonesoup.updater.kalman import KalmanUpdater
from stonesoup.updater.pointprocess import PHDUpdater

TUTORIAL_GATE = 3.0  # the tutorial's missed_distance (Mahalanobis, not squared)


def build_filter(params, gate_distance):
    """The tutorial's components with the demo's parameters (see README for the mapping)."""
    # Stone Soup's state is [x, vx, y, vy]; ConstantVelocity(q) has
    # Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]] per axis: the same continuous white-noise
    # acceleration as gmphd's ConstantVelocity(2, sigma_v) with q = sigma_v^2 = 25.
    q = params["sigma_v"] ** 2
    transition_model = CombinedLinearGaussianTransitionModel(
        (ConstantVelocity(q), ConstantVelocity(q)))
    sigma = params["measurement_sigma"]
    measurement_model = LinearGaussian(
        ndim_state=4, mapping=(0, 2), noise_covar=np.diag([sigma**2, sigma**2]))
    (x0, x1), (y0, y1) = params["region"]
    # Clutter intensity kappa = rate / area, uniform over the region: 60 / 2000^2 m^-2.
    clutter_spatial_density = params["clutter_rate"] / ((x1 - x0) * (y1 - y0))
    return (measurement_model, *tutorial_filter(
        KalmanPredictor(transition_model), KalmanUpdater(measurement_model),
        clutter_spatial_density, params, gate_distance))


def tutorial_filter(predictor, kalman_updater, clutter_spatial_density, params, gate_distance):
    """The GM-PHD tutorial's hypothesiser, PHD updater and reducer around a predictor and a
    Kalman-type updater (linear or unscented): (hypothesiser, updater, reducer)."""
    updater = PHDUpdater(
        kalman_updater,
        clutter_spatial_density=clutter_spatial_density,
        prob_detection=params["p_detection"],
        prob_survival=params["p_survival"])
    base_hypothesiser = DistanceHypothesiser(
        predictor, kalman_updater, Mahalanobis(), missed_distance=gate_distance)
    hypothesiser = GaussianMixtureHypothesiser(base_hypothesiser, order_by_detection=True)
    # Vo & Ma's T = 1e-5, U = 4 (squared Mahalanobis, as Stone Soup's merge_threshold),
    # J_max = 100.
    reducer = GaussianMixtureReducer(
        prune_threshold=params["prune"], pruning=True,
        merge_threshold=params["merge"], merging=True,
        max_number_components=params["max_components"], truncating=True)
    return hypothesiser, updater, reducer


def births(params, timestamp):
    """Fresh birth components at the scan time (the tutorial re-adds its birth component
    each step with the scan's timestamp, so the prediction leaves it as given)."""
    cov = np.diag([params["birth_cov_diag"]] * 4)
    return [TaggedWeightedGaussianState(
        state_vector=[[x], [0.0], [y], [0.0]], covar=cov, weight=params["birth_weight"],
        tag=TaggedWeightedGaussianState.BIRTH, timestamp=timestamp)
        for x, y in params["birth_means_xy"]]


def extract(components):
    """Vo & Ma's extraction: round(w) copies of each component with w > 0.5.
    floor(w + 0.5) rounds halves up like MATLAB/Rust round (Python's round() would not)."""
    out = []
    for c in components:
        if c.weight > 0.5:
            out += [(float(c.state_vector[0, 0]), float(c.state_vector[2, 0]))] \
                * int(math.floor(float(c.weight) + 0.5))
    return out


def ospa(truth, estimates, c=100.0):
    """OSPA (Schuhmacher, Vo & Vo 2008) of order p = 1 with cut-off c."""
    m, n = len(truth), len(estimates)
    if m == 0 and n == 0:
        return 0.0
    if m == 0 or n == 0:
        return c
    d = np.minimum(np.linalg.norm(
        np.asarray(truth)[:, None, :] - np.asarray(estimates)[None, :, :], axis=2), c)
    rows, cols = linear_sum_assignment(d)
    return (d[rows, cols].sum() + c * abs(m - n)) / max(m, n)


def run_one(scans, truth, params, gate_distance):
    """One Monte-Carlo run of the linear demo (see run_scans)."""
    return run_scans(scans, truth, params, build_filter(params, gate_distance), births,
                     lambda z: np.array([[z[0]], [z[1]]]))


def run_scans(scans, truth, params, parts, births_at, measurement_vector):
    """One Monte-Carlo run of the filter `parts` (build_filter's four), with the births
    `births_at(params, timestamp)` and each measurement as `measurement_vector(z)`;
    returns per-step OSPA, count-right flags, estimated counts, per-scan seconds and
    mixture sizes."""
    measurement_model, hypothesiser, updater, reducer = parts
    start = datetime(2000, 1, 1)
    reduced_states = []  # the intensity starts empty, as in the Rust tests
    ospas, right, counts, seconds, sizes = [], [], [], [], []
    for k, (scan, objects) in enumerate(zip(scans, truth), start=1):
        timestamp = start + timedelta(seconds=k * params["dt_s"])
        # A list, not the tutorial's set, so that runs are reproducible (set order
        # follows object addresses); the reducer sorts by weight either way.
        detections = [Detection(measurement_vector(z), timestamp=timestamp,
                                measurement_model=measurement_model) for z in scan]
        t0 = time.perf_counter()
        current_state = reduced_states + births_at(params, timestamp)
        hypotheses = hypothesiser.hypothesise(
            current_state, detections, timestamp=timestamp, order_by_detection=True)
        updated_states = updater.update(hypotheses)
        reduced_states = list(reducer.reduce(updated_states))
        seconds.append(time.perf_counter() - t0)
        estimates = extract(reduced_states)
        ospas.append(ospa(objects, estimates, params["ospa_c"]))
        right.append(len(estimates) == len(objects))
        counts.append(len(estimates))
        sizes.append(len(reduced_states))
    return ospas, right, counts, seconds, sizes


def add_gate_options(parser):
    """--gated (the tutorial's gate, default) | --ungated | --gate-distance D."""
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--gated", action="store_true", help="missed_distance=3 (default)")
    mode.add_argument("--ungated", action="store_true", help="missed_distance=inf")
    mode.add_argument("--gate-distance", type=float, help="missed_distance=D")


def gate_distance_of(args):
    """The DistanceHypothesiser's missed_distance that add_gate_options' flags ask for."""
    if args.ungated:
        return float("inf")
    if args.gate_distance is not None:
        return args.gate_distance
    return TUTORIAL_GATE


def score_runs(runs, truth, run, describe):
    """Runs `run(scans)` (-> run_one's lists) on every run, prints each run's and the
    overall figures; `describe` names the configuration on the RESULT line."""
    all_ospa, all_right, all_counts, all_seconds, all_sizes = [], [], [], [], []
    for one in runs:
        o, r, n, s, j = run(one["scans"])
        all_ospa += o
        all_right += r
        all_counts += n
        all_seconds += s
        all_sizes += j
        print(f"  seed {one['seed']}: mean OSPA {np.mean(o):.2f} m, count right "
              f"{100 * np.mean(r):.0f} %, median {1e3 * statistics.median(s):.1f} ms/scan",
              flush=True)

    true_counts = [len(objects) for _ in runs for objects in truth]
    print(f"RESULT {describe} runs={len(runs)} "
          f"steps={len(all_ospa)}: mean OSPA {np.mean(all_ospa):.4f} m, "
          f"count right {100 * np.mean(all_right):.1f} %, mean count "
          f"{np.mean(all_counts):.2f} estimated vs {np.mean(true_counts):.2f} true, "
          f"median {1e3 * statistics.median(all_seconds):.2f} ms/scan "
          f"(mean {1e3 * np.mean(all_seconds):.2f}), mean {np.mean(all_sizes):.1f} components")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", help="JSON from the vo_demo_export example")
    parser.add_argument("--runs", type=int, default=None, help="first N runs (default all)")
    add_gate_options(parser)
    args = parser.parse_args()
    gate_distance = gate_distance_of(args)

    with open(args.data) as f:
        data = json.load(f)
    params, truth = data["parameters"], data["truth"]
    runs = data["runs"][:args.runs]
    total = sum(len(s) for r in data["runs"] for s in r["scans"])
    print(f"data: {len(data['runs'])} runs (seeds {data['seeds'][0]}..{data['seeds'][-1]}), "
          f"{total} measurements; run 0 step 1 has {len(data['runs'][0]['scans'][0])}")
    print(f"Stone Soup GM-PHD, missed_distance={gate_distance}, {len(runs)} runs x "
          f"{len(truth)} steps", flush=True)
    score_runs(runs, truth, lambda scans: run_one(scans, truth, params, gate_distance),
               f"missed_distance={gate_distance}")


if __name__ == "__main__":
    main()
