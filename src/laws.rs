//! Published laws the page and the validation draw beside the model: the run-out and final
//! height of granular column collapses (Lube et al.), and the plane-strain friction angle of
//! the paper's Drucker–Prager cone (stated with the cone in `material`, named here too). One
//! place for each formula; the validation cases
//! (`tests/support/validation.rs`), the benches and the page's floor markers call these.
//!
//! Aspect ratio a = H0/L0 (plane: L0 the half-width of the column) or H0/R0 (axisymmetric: R0
//! the column's radius); run-outs are normalised as (L∞ − L0)/L0, heights as H∞/H0.

use serde::{Deserialize, Serialize};

/// Lube, Huppert, Sparks & Freundt (2005), plane collapses: (L∞ − L0)/L0 = 1.2 a for
/// a ≲ 2.3, 1.9 a^(2/3) above (one value at every a: the validation's reference).
pub fn lube_runout(a: f64) -> f64 {
    if a < 2.3 {
        1.2 * a
    } else {
        1.9 * a.powf(2.0 / 3.0)
    }
}

/// Lube et al. (2005), plane collapses: H∞/H0 = 1 for a ≲ 1.15 (the top is not reached by
/// the failure), H∞/L0 ≈ a^(2/5) above, i.e. H∞/H0 = a^(−3/5).
pub fn lube_height(a: f64) -> f64 {
    if a < 1.15 { 1.0 } else { a.powf(-0.6) }
}

/// Lube et al. (2005), plane collapses, with their transition: 1.2 a below a = 1.8,
/// 1.9 a^(2/3) above a = 2.8, and between the two the range the two laws span
/// (`[low, high]`, normalised run-out).
pub fn lube_runout_range(a: f64) -> [f64; 2] {
    let (linear, power) = (1.2 * a, 1.9 * a.powf(2.0 / 3.0));
    if a < 1.8 {
        [linear, linear]
    } else if a > 2.8 {
        [power, power]
    } else {
        [linear.min(power), linear.max(power)]
    }
}

/// Lube, Huppert, Sparks & Hallworth (2004) and Lajeunesse, Mangeney-Castelnau & Vilotte
/// (2004), axisymmetric collapses: (R∞ − R0)/R0 = 1.24 a for a ≲ 1.7, 1.6 a^(1/2) above.
pub fn lube_axisymmetric_runout(a: f64) -> f64 {
    if a < 1.7 { 1.24 * a } else { 1.6 * a.sqrt() }
}

/// Lube et al. (2004), axisymmetric collapses: H∞/R0 = a for a ≲ 0.74 (the top is not
/// reached by the failure), H∞/R0 ≈ 0.88 a^(1/6) above; returned as H∞/H0.
pub fn lube_axisymmetric_height(a: f64) -> f64 {
    if a < 0.74 {
        1.0
    } else {
        0.88 * a.powf(1.0 / 6.0) / a
    }
}

/// Lajeunesse, Mangeney-Castelnau & Vilotte (2004), axisymmetric collapses: H∞/R0 = a for
/// a ≲ 0.74, then about 0.74 whatever a; returned as H∞/H0.
pub fn lajeunesse_axisymmetric_height(a: f64) -> f64 {
    a.min(0.74) / a
}

/// The plane-strain angle of the paper's Drucker–Prager cone, stated with the cone
/// ([`crate::material::plane_strain_angle`]).
pub use crate::material::plane_strain_angle;

/// What a column of aspect ratio `a` would do by the experiments, for the floor markers of a
/// collapse: the run-out (normalised, `[low, high]`, equal outside a transition) and the
/// final height H∞/H0, with the regime and the source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CollapseLaw {
    pub aspect_ratio: f64,
    pub runout: [f64; 2],
    pub height: f64,
    /// Which branch of the law applies, in words.
    pub regime: String,
    /// The publication the numbers come from.
    pub source: String,
}

/// The law for a plane (`dim` 2) or axisymmetric (`dim` 3) collapse of aspect ratio `a`.
pub fn collapse_law(dim: usize, a: f64) -> CollapseLaw {
    if dim == 2 {
        let regime = if a < 1.8 {
            "a < 1.8: run-out 1.2 a"
        } else if a > 2.8 {
            "a > 2.8: run-out 1.9 a^(2/3)"
        } else {
            "1.8 ≤ a ≤ 2.8: between 1.2 a and 1.9 a^(2/3)"
        };
        CollapseLaw {
            aspect_ratio: a,
            runout: lube_runout_range(a),
            height: lube_height(a),
            regime: regime.into(),
            source: "Lube et al. (2005), plane collapses".into(),
        }
    } else {
        let r = lube_axisymmetric_runout(a);
        CollapseLaw {
            aspect_ratio: a,
            runout: [r, r],
            height: lube_axisymmetric_height(a),
            regime: if a < 1.7 {
                "a < 1.7: run-out 1.24 a".into()
            } else {
                "a ≥ 1.7: run-out 1.6 a^(1/2)".into()
            },
            source: "Lube et al. (2004), axisymmetric collapses".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plane_law_spans_its_transition() {
        assert_eq!(lube_runout_range(1.0), [1.2, 1.2]);
        let p3 = 1.9 * 3f64.powf(2.0 / 3.0);
        assert_eq!(lube_runout_range(3.0), [p3, p3]);
        // in the transition the range holds both laws, and the single-valued law lies in it
        for a in [1.8, 2.0, 2.3, 2.5, 2.8] {
            let [lo, hi] = lube_runout_range(a);
            assert!(lo < hi, "{a}");
            assert_eq!(lo, 1.2 * a);
            assert!((hi - 1.9 * a.powf(2.0 / 3.0)).abs() < 1e-12);
            assert!(lube_runout(a) >= lo && lube_runout(a) <= hi);
        }
        let law = collapse_law(2, 2.0);
        assert!(law.source.contains("2005") && law.regime.contains("between"));
        assert!(collapse_law(3, 1.0).source.contains("2004"));
    }

    #[test]
    fn heights_start_at_the_column_and_fall() {
        assert_eq!(lube_height(1.0), 1.0);
        assert!((lube_height(2.0) - 2f64.powf(-0.6)).abs() < 1e-12);
        assert_eq!(lube_axisymmetric_height(0.5), 1.0);
        assert!(lube_axisymmetric_height(3.0) < lube_axisymmetric_height(1.0));
        assert!((lajeunesse_axisymmetric_height(2.0) - 0.37).abs() < 1e-12);
    }
}
