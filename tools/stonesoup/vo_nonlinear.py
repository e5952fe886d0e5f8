"""Stone Soup's GM-PHD on Vo & Ma's nonlinear demo, on the data of gmphd/benches/scans.rs.

Reads the JSON written by `cargo run --release -p gmphd --example vo_nonlinear_export -- FILE`
(the `vo_nonlinear` scenario of the benchmark: 10 targets on coordinated turns, a
bearing-range sensor at the origin, N seeded runs x 100 steps, run 0 = the benchmark's),
runs Stone Soup's unscented GM-PHD on every scan and scores it like vo_linear.py (whose
extraction and OSPA are imported, not copied): Vo & Ma's extraction, OSPA c = 100 m,
p = 1 on positions, per step; mean over all runs x steps.

The filter is the one of Stone Soup's GM-PHD tutorial (as in vo_linear.py) with the
unscented pieces: UnscentedKalmanPredictor(ConstantTurn) + UnscentedKalmanUpdater
(CartesianToBearingRange), both with the demo's (and our) unscented parameters
alpha = 1, beta = 2, kappa = 2; DistanceHypothesiser(Mahalanobis, missed_distance) inside
a GaussianMixtureHypothesiser, PHDUpdater, GaussianMixtureReducer; per step the birth
components are added with the scan's timestamp, then hypothesise, update, reduce.

Process noise (--noise): Stone Soup 1.9.1's ConstantTurn has, per axis,
Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]] (continuous white acceleration) and q_w dt on the turn
rate; ours (and Vo & Ma's) is sigma_v^2 G G^T with G = [dt^2/2, dt] per axis and
(sigma_w dt)^2 on the turn rate. With dt = 1 s the only difference is the position
variance, q/3 against sigma_v^2/4. `--noise vo` (default) uses ConstantTurn with its
covar() replaced by ours (same transition function), `--noise stonesoup` ConstantTurn as
shipped with q = sigma_v^2 and q_w = sigma_w^2.

Gating as in vo_linear.py: --gated (default) is the tutorial's missed_distance=3,
--ungated is missed_distance=inf, --gate-distance D another gate.

Usage: python vo_nonlinear.py DATA.json [--runs N] [--gated | --ungated | --gate-distance D]
                              [--noise vo|stonesoup]
"""

import argparse
import json

import numpy as np
from scipy.linalg import block_diag

from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
from stonesoup.models.transition.nonlinear import ConstantTurn
from stonesoup.predictor.kalman import UnscentedKalmanPredictor
from stonesoup.types.angle import Bearing
from stonesoup.types.array import CovarianceMatrix, StateVector
from stonesoup.types.state import TaggedWeightedGaussianState
from stonesoup.updater.kalman import UnscentedKalmanUpdater

from vo_linear import add_gate_options, gate_distance_of, run_scans, score_runs, tutorial_filter


class VoMaConstantTurn(ConstantTurn):
    """ConstantTurn (same state order [x, vx, y, vy, w] and transition function) with
    Vo & Ma's (and gmphd's CoordinatedTurn's) process noise: per axis
    sigma_v^2 [[dt^4/4, dt^3/2], [dt^3/2, dt^2]], and (sigma_w dt)^2 on the turn rate.
    Here linear_noise_coeffs = [sigma_v^2, sigma_v^2], turn_noise_coeff = sigma_w^2."""

    def covar(self, time_interval, **kwargs):
        q_x, q_y = self.linear_noise_coeffs
        dt = abs(time_interval.total_seconds())
        g = np.array([[dt**4 / 4., dt**3 / 2.], [dt**3 / 2., dt**2]])
        return CovarianceMatrix(block_diag(g * q_x, g * q_y, self.turn_noise_coeff * dt**2))


def build_filter(params, gate_distance, noise):
    """The tutorial's components, unscented, with the demo's parameters (README mapping)."""
    q = params["sigma_v"] ** 2
    q_turn = params["sigma_turn"] ** 2
    model_class = VoMaConstantTurn if noise == "vo" else ConstantTurn
    transition_model = model_class(linear_noise_coeffs=np.array([q, q]), turn_noise_coeff=q_turn)
    sigma_bearing, sigma_range = params["noise_std_bearing_range"]
    # Bearing = atan2(y - y_s, x - x_s) from the x axis, sensor at the origin (default
    # translation and rotation offsets are zero), as gmphd's BearingRange.
    measurement_model = CartesianToBearingRange(
        ndim_state=5, mapping=(0, 2),
        noise_covar=np.diag([sigma_bearing**2, sigma_range**2]))
    ut = params["unscented"]
    updater_ukf = UnscentedKalmanUpdater(
        measurement_model, alpha=ut["alpha"], beta=ut["beta"], kappa=ut["kappa"])
    predictor = UnscentedKalmanPredictor(
        transition_model, alpha=ut["alpha"], beta=ut["beta"], kappa=ut["kappa"])
    # Clutter intensity kappa = rate / volume of our clutter region
    # [-pi, pi) x [0, max_range]: 20 / (2 pi 2000) per rad m.
    (b0, b1), (r0, r1) = params["clutter_region_bearing_range"]
    clutter_spatial_density = params["clutter_rate"] / ((b1 - b0) * (r1 - r0))
    return (measurement_model, *tutorial_filter(
        predictor, updater_ukf, clutter_spatial_density, params, gate_distance))


def births(params, timestamp):
    """Fresh birth components at the scan time, state [x, vx, y, vy, w]."""
    sx, sy, svx, svy, sw = params["birth_std"]
    cov = np.diag([sx**2, svx**2, sy**2, svy**2, sw**2])
    return [TaggedWeightedGaussianState(
        state_vector=[[b["xy"][0]], [0.0], [b["xy"][1]], [0.0], [0.0]], covar=cov,
        weight=b["weight"], tag=TaggedWeightedGaussianState.BIRTH, timestamp=timestamp)
        for b in params["births"]]


def run_one(scans, truth, params, gate_distance, noise):
    """One Monte-Carlo run of the nonlinear demo (vo_linear.run_scans)."""
    return run_scans(scans, truth, params, build_filter(params, gate_distance, noise), births,
                     lambda z: StateVector([Bearing(z[0]), z[1]]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", help="JSON from the vo_nonlinear_export example")
    parser.add_argument("--runs", type=int, default=None, help="first N runs (default all)")
    parser.add_argument("--noise", choices=("vo", "stonesoup"), default="vo",
                        help="process noise: Vo & Ma's / ours (default) or ConstantTurn's")
    add_gate_options(parser)
    args = parser.parse_args()
    gate_distance = gate_distance_of(args)

    with open(args.data) as f:
        data = json.load(f)
    params, truth = data["parameters"], data["truth"]
    runs = data["runs"][:args.runs]
    total = sum(len(s) for r in data["runs"] for s in r["scans"])
    print(f"data: {len(data['runs'])} runs (seeds {data['seeds'][0]}..{data['seeds'][-1]}), "
          f"{total} measurements; run 0 has {sum(len(s) for s in data['runs'][0]['scans'])}")
    print(f"Stone Soup unscented GM-PHD, missed_distance={gate_distance}, noise={args.noise}, "
          f"{len(runs)} runs x {len(truth)} steps", flush=True)
    score_runs(runs, truth,
               lambda scans: run_one(scans, truth, params, gate_distance, args.noise),
               f"missed_distance={gate_distance} noise={args.noise}")


if __name__ == "__main__":
    main()
