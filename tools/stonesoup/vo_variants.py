"""Diagnostic: why Stone Soup's GM-PHD scores differently from ours on the same data.

Runs vo_linear.py's filter (same data, same parameters, same scoring) with Stone Soup's
departures from Vo & Ma's published algorithm (which gmphd implements) undone, one at
a time and all together. Nothing here tunes either filter; it only checks that the
parameter mapping is right and says where a difference in the figures comes from.

Stone Soup 1.9.1's departures (read from its source):
  cap     GaussianMixtureReducer.merge_components caps a merged weight at 1.
  prune   prune() spreads the pruned weight evenly over the survivors (Vo: drops it).
  births  a birth component's missed-detection term is dropped (PHDUpdater keeps
          only non-'birth' tags), and its detected terms are multiplied by p_S
          (the hypothesiser re-tags them, so the updater's `tag != 'birth'` test
          passes). Vo: a birth component gives p_D w q / (...) per measurement and
          (1 - p_D) w when missed, without p_S.
  merge   merge() measures each candidate's squared Mahalanobis distance with the
          candidate's own covariance, against the running merged component; Vo uses
          the heaviest component's covariance and mean, fixed for the whole cluster.

Usage: python vo_variants.py DATA.json [--runs N] [--gate-distance D] [--variants V ...]
                             [--demo linear|nonlinear]
with VARIANT among: tutorial cap prune births merge vo (default: all of them).
--demo nonlinear runs vo_nonlinear.py's filter (unscented, Vo & Ma's process noise) on
the JSON of the vo_nonlinear_export example instead.
"""

import argparse
import json
import uuid

import numpy as np
from stonesoup.mixturereducer.gaussianmixture import GaussianMixtureReducer
from stonesoup.types.state import TaggedWeightedGaussianState

import vo_linear
import vo_nonlinear


class VoReducer(GaussianMixtureReducer):
    """GaussianMixtureReducer with the chosen departures replaced by Vo & Ma's rules."""

    undo = set()

    def prune(self, components):
        if "prune" not in self.undo:
            return super().prune(components)
        return [c for c in components if c.weight >= self.prune_threshold]

    def merge_components(self, c1, c2):
        merged = super().merge_components(c1, c2)
        if "cap" in self.undo:
            merged.weight = c1.weight + c2.weight
        return merged

    def merge(self, components):
        if "merge" not in self.undo:
            return super().merge(components)
        # Vo & Ma Table II: the heaviest component j, every i with
        # (m_i - m_j)' P_j^-1 (m_i - m_j) <= U, merged by moment matching.
        remaining = sorted(components, key=lambda c: float(c.weight), reverse=True)
        out = []
        while remaining:
            best = remaining[0]
            inv = np.linalg.inv(best.covar)
            close, rest = [], []
            for c in remaining:
                d = np.asarray(c.state_vector - best.state_vector, dtype=float)
                (close if (d.T @ inv @ d).item() <= self.merge_threshold else rest).append(c)
            w = np.array([float(c.weight) for c in close])
            means = [np.asarray(c.state_vector, dtype=float) for c in close]
            mean = sum(wi * m for wi, m in zip(w, means)) / w.sum()
            covar = sum(wi * (np.asarray(c.covar) + (mean - m) @ (mean - m).T)
                        for wi, c, m in zip(w, close, means)) / w.sum()
            if "cap" not in self.undo:
                w_total = min(w.sum(), 1.0)  # keep Stone Soup's cap unless undone too
            else:
                w_total = w.sum()
            out.append(TaggedWeightedGaussianState(
                state_vector=mean, covar=covar, weight=w_total, tag=best.tag,
                timestamp=best.timestamp))
            remaining = rest
        return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data")
    parser.add_argument("--runs", type=int, default=None)
    parser.add_argument("--gate-distance", type=float, default=vo_linear.TUTORIAL_GATE)
    parser.add_argument("--variants", nargs="+",
                        default=["tutorial", "cap", "prune", "births", "merge", "vo"])
    parser.add_argument("--demo", choices=("linear", "nonlinear"), default="linear")
    args = parser.parse_args()
    demo = vo_linear if args.demo == "linear" else vo_nonlinear
    with open(args.data) as f:
        data = json.load(f)
    truth, runs = data["truth"], data["runs"][:args.runs]

    # Both demos build their reducer in vo_linear.tutorial_filter(), which now makes a VoReducer.
    vo_linear.GaussianMixtureReducer = VoReducer
    tutorial_births = demo.births
    for variant in args.variants:
        undo = {"cap", "prune", "births", "merge"} if variant == "vo" else {variant} - {"tutorial"}
        VoReducer.undo = undo
        params = dict(data["parameters"])
        if "births" in undo:
            # Untagged birth components of weight w / p_S: the updater's p_S factor then
            # gives exactly Vo's p_D w q and (1 - p_D) w, and the missed term is kept.
            if args.demo == "linear":
                params["birth_weight"] = params["birth_weight"] / params["p_survival"]
            else:
                params["births"] = [dict(b, weight=b["weight"] / params["p_survival"])
                                    for b in params["births"]]
            demo.births = lambda p, t: [
                TaggedWeightedGaussianState.from_state(b, tag=str(uuid.uuid4()))
                for b in tutorial_births(p, t)]
        else:
            demo.births = tutorial_births
        ospas, right, counts = [], [], []
        for run in runs:
            extra = () if args.demo == "linear" else ("vo",)  # nonlinear: Vo & Ma's noise
            o, r, n, _, _ = demo.run_one(run["scans"], truth, params, args.gate_distance, *extra)
            ospas += o
            right += r
            counts += n
        print(f"{variant:8s} undone={sorted(undo)} gate={args.gate_distance} runs={len(runs)}: "
              f"mean OSPA {np.mean(ospas):.4f} m, count right {100 * np.mean(right):.1f} %, "
              f"mean count {np.mean(counts):.2f}", flush=True)


if __name__ == "__main__":
    main()
