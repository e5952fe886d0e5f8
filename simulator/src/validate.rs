//! Checks of a scenario's values, reporting the offending key by its path in the file.

use std::collections::HashSet;

use crate::error::{invalid, ScenarioError};
use crate::motion::Motion;
use crate::scenario::Scenario;
use crate::target::Target;

/// Checks every value of `scenario`; the first problem found is returned.
pub(crate) fn validate(scenario: &Scenario) -> Result<(), ScenarioError> {
    if let Some(start) = scenario.start {
        require(
            start.is_finite() && start >= 0.0,
            "start",
            start,
            "a Unix time ≥ 0",
        )?;
    }
    require_positive(scenario.duration_s, "duration_s")?;
    require_positive(scenario.truth_rate_hz, "truth_rate_hz")?;
    if let Some(space) = scenario.personal_space_m {
        require_positive(space, "personal_space_m")?;
    }

    let mut ids = HashSet::new();
    for (i, target) in scenario.targets.iter().enumerate() {
        let key = format!("targets[{i}]");
        if !ids.insert(target.id) {
            return Err(invalid(
                format!("{key}.id"),
                format!("id {} is used by another target", target.id),
            ));
        }
        validate_target(target, &key)?;
    }

    let mut names = HashSet::new();
    for (i, spec) in scenario.sensors.iter().enumerate() {
        let key = format!("sensors[{i}]");
        if !names.insert(spec.sensor.as_str()) {
            return Err(invalid(
                format!("{key}.sensor"),
                format!("name `{}` is used by another sensor", spec.sensor),
            ));
        }
        let p_d = spec.detection_probability;
        require(
            p_d > 0.0 && p_d <= 1.0,
            &format!("{key}.detection_probability"),
            p_d,
            "a probability in (0, 1]",
        )?;
        require_non_negative(spec.clutter_rate, &format!("{key}.clutter_rate"))?;
        require_positive(spec.rate_hz, &format!("{key}.rate_hz"))?;
        require_non_negative(spec.phase_s, &format!("{key}.phase_s"))?;
        let descriptor = spec.descriptor(&scenario.site);
        descriptor
            .validate()
            .map_err(|source| ScenarioError::Descriptor {
                key: key.clone(),
                source,
            })?;
        sensor_models::measurement_model(&descriptor).map_err(|source| {
            ScenarioError::SensorModel {
                key: format!("{key}.model"),
                source,
            }
        })?;
    }
    Ok(())
}

/// Checks one target's times and motion.
fn validate_target(target: &Target, key: &str) -> Result<(), ScenarioError> {
    require_non_negative(target.appear_s, &format!("{key}.appear_s"))?;
    if let Some(end) = target.disappear_s {
        require(
            end.is_finite() && end > target.appear_s,
            &format!("{key}.disappear_s"),
            end,
            "a time after appear_s",
        )?;
    }
    let key = format!("{key}.motion");
    match &target.motion {
        Motion::ConstantVelocity(cv) => {
            require_finite_point(&cv.position, &format!("{key}.position"))?;
            require_finite_point(&cv.velocity, &format!("{key}.velocity"))
        }
        Motion::RandomWalk(walk) => {
            let bounds = &walk.bounds;
            require_finite_point(&bounds.min, &format!("{key}.bounds.min"))?;
            require_finite_point(&bounds.max, &format!("{key}.bounds.max"))?;
            if (0..3).any(|i| bounds.min[i] > bounds.max[i]) {
                return Err(invalid(
                    format!("{key}.bounds"),
                    format!("min {:?} exceeds max {:?}", bounds.min, bounds.max),
                ));
            }
            require_finite_point(&walk.position, &format!("{key}.position"))?;
            if !bounds.contains(&walk.position) {
                return Err(invalid(
                    format!("{key}.position"),
                    format!("{:?} is outside the bounds box", walk.position),
                ));
            }
            for (axis, std) in walk.std.iter().enumerate() {
                require_non_negative(*std, &format!("{key}.std[{axis}]"))?;
            }
            if let Some(dt) = walk.knot_interval_s {
                require_positive(dt, &format!("{key}.knot_interval_s"))?;
            }
            Ok(())
        }
        Motion::Waypoints(path) => {
            if path.points.is_empty() {
                return Err(invalid(format!("{key}.points"), "needs at least one point"));
            }
            let mut previous = f64::NEG_INFINITY;
            for (i, (t, p)) in path.points.iter().enumerate() {
                let point_key = format!("{key}.points[{i}]");
                require(
                    t.is_finite() && *t > previous,
                    &point_key,
                    *t,
                    "a finite time after the previous point's",
                )?;
                require_finite_point(p, &point_key)?;
                previous = *t;
            }
            Ok(())
        }
    }
}

/// Fails with `expected` when `ok` is false.
fn require(ok: bool, key: &str, value: f64, expected: &str) -> Result<(), ScenarioError> {
    if ok {
        Ok(())
    } else {
        Err(invalid(key, format!("{value} is not {expected}")))
    }
}

fn require_positive(value: f64, key: &str) -> Result<(), ScenarioError> {
    require(
        value.is_finite() && value > 0.0,
        key,
        value,
        "a finite number > 0",
    )
}

fn require_non_negative(value: f64, key: &str) -> Result<(), ScenarioError> {
    require(
        value.is_finite() && value >= 0.0,
        key,
        value,
        "a finite number ≥ 0",
    )
}

fn require_finite_point(p: &[f64; 3], key: &str) -> Result<(), ScenarioError> {
    if p.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(invalid(key, format!("{p:?} has a non-finite coordinate")))
    }
}
