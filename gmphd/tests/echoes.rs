//! Side peaks of a microphone pair's TDOA (`gmphd::echoes`): a measurement δ to one side of a
//! component's predicted TDOA is weighed and applied as that component's detection at z ∓ δ.

use gmphd::update::Updater;
use gmphd::MeasurementModel;
use gmphd::{
    Detection, Echoes, Gating, Gaussian, GaussianMixture, Label, Measurement, MicPair, RandomWalk,
    UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};

const HEIGHT: f64 = 1.5;
const CLUTTER_RATE: f64 = 1.0;
const P_D: f64 = 0.8;
const WEIGHT: f64 = 0.9;
const OFFSET: f64 = 2.8e-4;
const RATE: f64 = 0.4;
const ECHOES: Echoes = Echoes {
    offset: OFFSET,
    rate: RATE,
};

fn pair() -> MicPair {
    let detection = Detection::new(P_D, CLUTTER_RATE).unwrap();
    MicPair::new(
        [1.25, 0.0, HEIGHT],
        [1.75, 0.0, HEIGHT],
        343.0,
        6.25e-5,
        detection,
    )
    .unwrap()
    .in_plane(HEIGHT)
    .unwrap()
}

fn prior() -> GaussianMixture {
    let talker = Gaussian::new(
        WEIGHT,
        DVector::from_vec(vec![1.0, 1.2]),
        DMatrix::identity(2, 2) * 0.01,
        Label(1),
    );
    GaussianMixture::from_components(vec![talker])
}

fn updater(echoes: Option<Echoes>) -> Updater {
    let mut updater = Updater::new(UnscentedParams::default(), Gating::OFF).unwrap();
    updater.set_echoes(echoes);
    updater
}

/// The posterior's detection children (the missed-detection copy is the first component) and
/// the measurement's U(z).
fn children(echoes: Option<Echoes>, z: f64) -> (Vec<Gaussian>, f64) {
    let motion = RandomWalk::new(2, 0.2, HEIGHT).unwrap();
    let outcome = updater(echoes)
        .update(
            &prior(),
            &motion,
            &pair(),
            &[Measurement::new(DVector::from_vec(vec![z]))],
        )
        .unwrap();
    (
        outcome.posterior.components[1..].to_vec(),
        outcome.association[0],
    )
}

/// q(z) of the talker's predicted TDOA, from the plain update's U(z) = p_D w q / (κ + p_D w q).
fn likelihood(z: f64) -> f64 {
    let (_, association) = children(None, z);
    let clutter_density = 1.0 / (2.0 * 0.5 / 343.0);
    CLUTTER_RATE * clutter_density * association / ((1.0 - association) * P_D * WEIGHT)
}

/// The talker's predicted TDOA: where the plain update's child does not move.
fn predicted_tdoa() -> f64 {
    // Its TDOA at the mean is close to the unscented mean; the plain update's child moves
    // linearly with z − ẑ, which finds the latter.
    let z0 = pair().measure(&Vector3::new(1.0, 1.2, HEIGHT))[0];
    let (child, _) = children(None, z0);
    let moved = child[0].mean[0] - 1.0;
    let (child, _) = children(None, z0 + 1e-5);
    let slope = (child[0].mean[0] - 1.0 - moved) / 1e-5;
    z0 - moved / slope
}

#[test]
fn a_side_peak_updates_its_talker_where_its_direct_path_would() {
    let predicted = predicted_tdoa();
    let (plain, _) = children(None, predicted);
    assert!((plain[0].mean[0] - 1.0).abs() < 1e-9, "{}", plain[0].mean);
    // A side peak δ above the prediction: the talker's children are its direct path (residual
    // δ), its lower side peak (residual 0) and its upper one (residual 2δ).
    let (sided, _) = children(Some(ECHOES), predicted + OFFSET);
    assert_eq!(sided.len(), 3);
    let (as_direct, _) = children(None, predicted + OFFSET);
    assert!((&sided[0].mean - &as_direct[0].mean).norm() < 1e-9);
    assert!((&sided[1].mean - &plain[0].mean).norm() < 1e-9);
    assert!((&sided[1].cov - &plain[0].cov).norm() < 1e-12);
    // Their weights are in the ratio q(δ) : ρ q(0) : ρ q(2δ).
    let q = [OFFSET, 0.0, 2.0 * OFFSET].map(|r| likelihood(predicted + r));
    let expected = [q[0], RATE * q[1], RATE * q[2]];
    for i in 1..3 {
        let ratio = sided[i].weight / sided[0].weight;
        let want = expected[i] / expected[0];
        assert!((ratio / want - 1.0).abs() < 1e-6, "{i}: {ratio} vs {want}");
    }
    // Explained by the talker (0.66 of it here, against 0.11 as a direct path 3 σ off).
    assert!(sided[1].weight > 0.5 && sided[1].weight > 5.0 * sided[0].weight);
}

#[test]
fn a_measurement_at_the_prediction_stays_mostly_a_direct_path() {
    let predicted = predicted_tdoa();
    let (sided, association) = children(Some(ECHOES), predicted);
    let (_, plain_association) = children(None, predicted);
    // Side-peak hypotheses δ away only add to how well the talker explains z.
    assert!(association >= plain_association);
    let heaviest = sided
        .iter()
        .max_by(|a, b| a.weight.total_cmp(&b.weight))
        .unwrap();
    assert!((heaviest.mean[0] - 1.0).abs() < 1e-9);
}
