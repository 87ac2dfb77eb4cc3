//! Errors, and the range checks that every parameter source (scene files, the builder, the
//! CLI and the page's sliders) goes through.

use std::fmt::Display;

/// Everything that can go wrong in setting up or running a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A parameter is out of its allowed range or of the wrong form.
    #[error("{field} = {value}: {allowed}")]
    Invalid {
        field: String,
        value: String,
        allowed: String,
    },
    /// A scene could not be parsed.
    #[error("{0}")]
    Parse(String),
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    /// The state went non-finite: the step stopped before the value could spread.
    #[error(
        "non-finite {quantity} at particle {particle} of body {body:?} in step {step}: the step went unstable (a smaller CFL number or a softer material helps)"
    )]
    NonFinite {
        body: String,
        particle: usize,
        quantity: &'static str,
        step: u64,
    },
    /// A body was compressed to no volume: an impact brought more energy per unit volume than
    /// its material law can store, or the step went unstable.
    #[error(
        "body {body:?} crushed to zero volume (particle {particle}, step {step}): compressed further than its material can resist, as by an impact bringing more energy than the material stores (a stiffer material or a slower body holds) or by an unstable step (a smaller CFL number holds)"
    )]
    Crushed {
        body: String,
        particle: usize,
        step: u64,
    },
    /// The stable time step is below [`crate::sim::MIN_DT`] (or a run would take more than
    /// [`crate::sim::MAX_STEPS`] steps): refused before stepping, or stopped where it fell.
    #[error(
        "the stable time step {dt:.3e} s is below the floor of {floor:.0e} s{when}: about {steps:.2e} steps per simulated second; {cause}"
    )]
    StepTooSmall {
        dt: f64,
        floor: f64,
        steps: f64,
        /// Where it happened ("" before stepping, " at step N (t = … s)" in a run).
        when: String,
        /// What sets the step and the setting to change.
        cause: String,
    },
    /// The live energy rose above the energy brought in by more than
    /// [`crate::sim::ENERGY_GUARD`]: the step went unstable.
    #[error(
        "the energy grew to {total:.4e} J from the {budget:.4e} J the bodies brought in (more than {margin:.0} % above) at step {step} (t = {time:.4} s): the step went unstable; {advice}"
    )]
    EnergyGrew {
        total: f64,
        budget: f64,
        margin: f64,
        step: u64,
        time: f64,
        advice: String,
    },
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An invalid value of `field`.
    pub fn invalid(
        field: impl Into<String>,
        value: impl Display,
        allowed: impl Into<String>,
    ) -> Self {
        Error::Invalid {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

/// `value` of `field` is none of `choices`: the error lists them.
pub fn not_one_of<S: AsRef<str>>(
    field: impl Into<String>,
    value: impl Display,
    choices: impl IntoIterator<Item = S>,
) -> Error {
    let names: Vec<String> = choices
        .into_iter()
        .map(|c| c.as_ref().to_string())
        .collect();
    Error::invalid(field, value, format!("must be one of {}", names.join(", ")))
}

/// `value` must be finite and `> 0`.
pub fn check_positive(field: impl Display, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            field.to_string(),
            value,
            format!("must be a finite number > 0{}", units(unit)),
        ))
    }
}

/// `value` must be finite and `>= 0`.
pub fn check_non_negative(field: impl Display, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            field.to_string(),
            value,
            format!("must be a finite number >= 0{}", units(unit)),
        ))
    }
}

/// `value` must lie in `[lo, hi]` (or `[lo, hi)` when `hi_open`).
pub fn check_range(
    field: impl Display,
    value: f64,
    lo: f64,
    hi: f64,
    hi_open: bool,
    unit: &str,
) -> Result<()> {
    let ok = value.is_finite() && value >= lo && if hi_open { value < hi } else { value <= hi };
    if ok {
        Ok(())
    } else {
        let close = if hi_open { ")" } else { "]" };
        Err(Error::invalid(
            field.to_string(),
            value,
            format!("must be in [{lo}, {hi}{close}{}", units(unit)),
        ))
    }
}

/// Every component must be finite.
pub fn check_finite_vec(field: impl Display, v: &[f64], unit: &str) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(
            format!("{field}[{i}]"),
            v[i],
            format!("must be a finite number{}", units(unit)),
        )),
    }
}

fn units(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" ({unit})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_field_the_value_and_the_range() {
        let e = check_range(
            "bodies[1].material.drucker_prager.friction_angle",
            95.0,
            0.0,
            90.0,
            true,
            "degrees",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "bodies[1].material.drucker_prager.friction_angle = 95: must be in [0, 90) (degrees)"
        );
        let e = check_positive("cell_size", f64::NAN, "m").unwrap_err();
        assert_eq!(
            e.to_string(),
            "cell_size = NaN: must be a finite number > 0 (m)"
        );
        assert!(check_non_negative("c", 0.0, "Pa").is_ok());
        assert!(
            check_finite_vec("gravity", &[0.0, f64::INFINITY], "m/s²")
                .unwrap_err()
                .to_string()
                .starts_with("gravity[1] = inf")
        );
    }
}
