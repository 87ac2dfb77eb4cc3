//! Non-associated Drucker–Prager plasticity for sand (Eq. 11–15), after Bui et al. (2008)
//! and An et al. (2016).
//!
//! Yield function f = √J2 + α_φ I1 − k_c, plastic potential g = √J2 + α_ψ I1 (Eq. 11–12), with
//! the plane-strain matching of Eq. 13 for sand at rest; by default the cone widens as a
//! particle flows, so that flowing sand stops at the angle where sand at rest starts to fail
//! ([`FrictionMatch::StartStop`], a departure from the paper; docs/validation.md). Stress is tension-positive (σ = −P I + s), so the cone
//! opens towards compression and its apex sits at I1 = k_c/α_φ.
//!
//! The plastic correction of Eq. 14, Δσ = −Δλ (3 α_ψ K I + (G/√J2) s), is applied to the elastic
//! trial stress with Δλ = f(σ_tr)/(G + 9 α_φ α_ψ K): the multiplier of Eq. 15 integrated over the
//! part of the step beyond the yield surface (it equals Δt·λ̇ of Eq. 15 when the step starts on
//! the surface), which lands the stress exactly on f = 0. Eq. 14's bulk term is K tr(ε̇) I.
//! Then Bui et al.'s two safeguards: a stress past the apex (tension) has its hydrostatic part
//! shifted back to the apex, and a remaining f > 0 is removed by scaling the deviatoric stress
//! back onto the cone. Cohesionless sand (c = 0) therefore carries no tension.
//!
//! Past the apex nothing resists an expansion: the grains part. The stress pass bounds their
//! volume, and in a body whose recipe closes them closes them again before it stresses them,
//! from the packed volume per unit mass this model gives ([`Constitutive::packed_specific_volume`], 1/ρ; `src/step/stress.rs`).
//!
//! Optionally the friction rises with the inertial number of the flow, μ(I) of Jop et al.
//! (2006) ([`super::mu_i`]): the cone's α_φ is then formed per particle from its strain rate
//! and pressure, and equals the rate-independent one at rest.

use super::mu_i::{MuI, MuIParams};
use super::{Constitutive, Elastic, ElasticParams, StressUpdate};
use crate::error::{Error, Result, check_non_negative, check_range};
use crate::math::{Number, Real, SymTensor};

const SQRT_3: Real = 1.732_050_8;

use serde::{Deserialize, Serialize};

/// Parameters: E (Pa), ν, density (kg/m³), friction angle φ ∈ [0°, 90°), dilatancy angle
/// ψ ∈ [0°, φ] and cohesion c ≥ 0 (Pa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DruckerPragerParams {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub friction_angle: f64,
    #[serde(default)]
    pub dilatancy_angle: f64,
    #[serde(default)]
    pub cohesion: f64,
    /// Rate-dependent friction μ(I) (off when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu_i: Option<MuIParams>,
    /// Which volumetric strain rate the stress update takes: each particle's own (the
    /// default) or its grid cell's average (against volumetric locking; [`VolumetricRate`]).
    #[serde(default, skip_serializing_if = "VolumetricRate::is_particle")]
    pub volumetric_rate: VolumetricRate,
    /// How the cone's constants follow from φ, ψ and c: Eq. 13's cone at rest widening as
    /// the sand flows (the default), Eq. 13 alone, or the steady-flow match
    /// ([`FrictionMatch`]).
    #[serde(default, skip_serializing_if = "FrictionMatch::is_default")]
    pub friction_match: FrictionMatch,
}

/// How the cone's α_φ, α_ψ and k_c follow from the friction angle φ, the dilatancy angle ψ
/// and the cohesion c.
///
/// With ψ = 0 the plastic flow is along the deviatoric stress s, so in steady simple shear (a
/// layer flowing parallel to a slope) every deviatoric component but the shear stress relaxes
/// away, and the layer carries τ = √J2 = k_c + 3 α_φ σ_n: it keeps flowing on any slope steeper
/// than atan(3 α_φ) (Davis 1968's reduced strength of non-associated flow). Eq. 13 matches the
/// cone to Mohr–Coulomb in plane strain for associated flow, so a φ = 32° sand of the paper
/// flows down to 26.9°, not 32°. The steady-flow match, α = tan θ / 3 and k_c = c, makes the
/// flowing layer mobilise τ = c + σ_n tan φ, the friction coefficient μ = tan φ that granular
/// rheologies measure from the angle of repose (Jop et al. 2006; Dunatunga & Kamrin 2015),
/// but a slope at rest, whose stress can take Mohr–Coulomb's orientation, then stands up to
/// asin(tan φ): 90° for φ = 45°. No cone of stress alone both starts a slope failing at an
/// angle and stops the flow at the same angle, so the default, the start–stop match, makes the
/// cone depend on the particle's history: Eq. 13's (start at φ_ps = asin 3 α_s) until the
/// particle has flowed, the steady-flow cone of the same φ_ps (3 α_f = tan φ_ps, stop at
/// φ_ps) once it has. Granular layers have a start–stop hysteresis of their own (Daerr &
/// Douady 1999, θ_start above θ_stop); this one undoes the non-associated flow's loss of
/// strength.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionMatch {
    /// α = tan θ / √(9 + 12 tan²θ), k_c = 3c / √(9 + 12 tan²φ) (Eq. 13, the paper's).
    PlaneStrain,
    /// α = tan θ / 3, k_c = c: a steadily shearing layer mobilises τ = c + σ_n tan φ.
    SteadyFlow,
    /// Eq. 13's cone at rest, widening with the particle's accumulated plastic strain to the
    /// steady-flow cone of the same plane-strain angle (3 α = tan φ_ps, reached at
    /// ε_p = [`FLOWING_STRAIN`]): a slope starts to fail and a flowing layer stops at the same
    /// angle φ_ps. The default.
    #[default]
    StartStop,
}

/// The arithmetic of the cone's formulas: `f64` for a body's constants, the solver's
/// numbers ([`Number`]: one particle, or four in lanes) for a friction that varies per particle.
pub trait ConeNumber:
    Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self> + std::ops::Div<Output = Self>
{
    /// The number `x`.
    fn of(x: f64) -> Self;
    /// The square root.
    fn root(self) -> Self;
}

impl<T: Number> ConeNumber for T {
    #[inline(always)]
    fn of(x: f64) -> Self {
        T::splat(x as Real)
    }
    #[inline(always)]
    fn root(self) -> Self {
        Number::sqrt(self)
    }
}

// With the `f64` feature f64 is the solver's number, covered above.
#[cfg(not(feature = "f64"))]
impl ConeNumber for f64 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn root(self) -> Self {
        f64::sqrt(self)
    }
}

/// √(12 μ² + 9), Eq. 13's root for a friction coefficient μ.
#[inline(always)]
fn eq13_root<T: ConeNumber>(mu: T) -> T {
    (mu * mu * T::of(12.0) + T::of(9.0)).root()
}

impl FrictionMatch {
    /// The scene-file names.
    pub const NAMES: [&'static str; 3] = ["plane_strain", "steady_flow", "start_stop"];

    pub fn is_default(&self) -> bool {
        *self == FrictionMatch::default()
    }

    /// The cone's α for a friction coefficient μ = tan θ: μ / √(12 μ² + 9) (Eq. 13), or μ / 3
    /// (steady flow); in `f64` for a body's constants, lane by lane for a friction that varies
    /// per particle (μ(I)).
    #[inline(always)]
    pub fn alpha<T: ConeNumber>(self, mu: T) -> T {
        match self {
            FrictionMatch::PlaneStrain | FrictionMatch::StartStop => mu / eq13_root(mu),
            FrictionMatch::SteadyFlow => mu * T::of(1.0 / 3.0),
        }
    }

    /// The cone's k_c for cohesion c and a friction coefficient μ = tan φ: 3c / √(12 μ² + 9)
    /// (Eq. 13), or c (steady flow).
    pub fn k_c(self, cohesion: f64, mu: f64) -> f64 {
        match self {
            FrictionMatch::PlaneStrain | FrictionMatch::StartStop => 3.0 * cohesion / eq13_root(mu),
            FrictionMatch::SteadyFlow => cohesion,
        }
    }

    /// The angle of repose (degrees) of the cone for a friction angle φ (degrees): a layer
    /// flowing down an infinite slope with ψ = 0 carries τ = 3 α σ_n with the flowing cone's
    /// α (see [`FrictionMatch`]), so it stops at atan(3 α): atan(sin φ_ps) for Eq. 13's cone,
    /// φ for the steady-flow match, φ_ps for the start–stop match.
    pub fn repose_angle(self, phi_deg: f64) -> f64 {
        match self {
            FrictionMatch::PlaneStrain | FrictionMatch::SteadyFlow => (3.0
                * self.alpha(phi_deg.to_radians().tan()))
            .atan()
            .to_degrees(),
            // 3 α_f = tan φ_ps
            FrictionMatch::StartStop => plane_strain_angle(phi_deg),
        }
    }

    /// The largest friction angle the match accepts (degrees, excluded): Eq. 13 takes any
    /// φ < 90°; the steady-flow cone 3 α_φ = tan φ reaches √3 at 60°, where its triaxial
    /// compression meridian passes through zero lateral stress (q = 3p) and beyond which it
    /// would ask for principal tension in compression.
    pub fn max_friction_angle(self) -> f64 {
        match self {
            FrictionMatch::PlaneStrain | FrictionMatch::StartStop => 90.0,
            FrictionMatch::SteadyFlow => 60.0,
        }
    }
}

/// The plane-strain Mohr–Coulomb angle (degrees) of the paper's Drucker–Prager cone with
/// ψ = 0 for a friction angle φ (degrees): sin φ_ps = 3 α_φ, with Eq. 13's
/// α_φ = tan φ / √(9 + 12 tan² φ).
pub fn plane_strain_angle(phi_deg: f64) -> f64 {
    let t = phi_deg.to_radians().tan();
    let alpha = FrictionMatch::PlaneStrain.alpha(t);
    (3.0 * alpha).asin().to_degrees()
}

/// Read by hand so that any wrong value names the allowed ones.
impl<'de> Deserialize<'de> for FrictionMatch {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> std::result::Result<Self, De::Error> {
        named(
            d,
            &Self::NAMES,
            &[
                FrictionMatch::PlaneStrain,
                FrictionMatch::SteadyFlow,
                FrictionMatch::StartStop,
            ],
        )
    }
}

/// Reads a string naming one of `values` (`names[i]` names `values[i]`), so that any wrong
/// value (a switch's `true` too) is an error naming the allowed ones.
fn named<'de, De: serde::Deserializer<'de>, T: Copy + 'static>(
    d: De,
    names: &'static [&'static str],
    values: &'static [T],
) -> std::result::Result<T, De::Error> {
    struct Names<T: 'static>(&'static [&'static str], &'static [T]);
    impl<T: Copy> serde::de::Visitor<'_> for Names<T> {
        type Value = T;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            let quoted: Vec<String> = self.0.iter().map(|n| format!("`{n}`")).collect();
            f.write_str(&quoted.join(" or "))
        }
        fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<T, E> {
            match self.0.iter().position(|n| *n == v) {
                Some(i) => Ok(self.1[i]),
                None => Err(E::unknown_variant(v, self.0)),
            }
        }
    }
    d.deserialize_str(Names(names, values))
}

/// Which volumetric strain rate tr ε̇ the stress update of a sand particle takes. With ψ = 0
/// the plastic flow of sand keeps its volume, and a coarse grid's velocity field sampled at
/// several particles per cell cannot shear without a spurious volume change that the elastic
/// bulk modulus resists (volumetric locking: the sand grows stronger with more particles per
/// cell). Averaging the volumetric part over each cell removes it (Coombs et al. 2018,
/// *Overcoming volumetric locking in material point methods*, CMAME 333); the stress pass
/// (`src/step/stress.rs`) does the averaging.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumetricRate {
    /// Each particle's own tr ε̇_p (the paper's).
    #[default]
    Particle,
    /// The volume-weighted mean of tr ε̇ over the body's particles in the particle's grid cell,
    /// with each particle's own deviatoric rate.
    CellAverage,
}

impl VolumetricRate {
    /// The scene-file names.
    pub const NAMES: [&'static str; 2] = ["particle", "cell_average"];

    pub fn is_particle(&self) -> bool {
        *self == VolumetricRate::Particle
    }
}

/// Read by hand so that any wrong value (a switch's `true` too) names the allowed ones.
impl<'de> Deserialize<'de> for VolumetricRate {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> std::result::Result<Self, De::Error> {
        named(
            d,
            &Self::NAMES,
            &[VolumetricRate::Particle, VolumetricRate::CellAverage],
        )
    }
}

impl DruckerPragerParams {
    pub fn elastic(&self) -> ElasticParams {
        ElasticParams {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
        }
    }
    pub fn validate(&self, path: &str) -> Result<()> {
        self.elastic().validate(path)?;
        let max = self.friction_match.max_friction_angle();
        check_range(
            format!("{path}.friction_angle"),
            self.friction_angle,
            0.0,
            max,
            true,
            match self.friction_match {
                FrictionMatch::PlaneStrain | FrictionMatch::StartStop => "degrees",
                FrictionMatch::SteadyFlow => "degrees, with the steady-flow friction match",
            },
        )?;
        let psi = self.dilatancy_angle;
        if !(psi.is_finite() && psi >= 0.0 && psi <= self.friction_angle) {
            return Err(Error::invalid(
                format!("{path}.dilatancy_angle"),
                psi,
                format!(
                    "must be in [0, {}] (degrees; at most the friction angle)",
                    self.friction_angle
                ),
            ));
        }
        check_non_negative(format!("{path}.cohesion"), self.cohesion, "Pa")?;
        match &self.mu_i {
            Some(m) => m.validate(&format!("{path}.mu_i")),
            None => Ok(()),
        }
    }
    /// The cone in p–q space for a particle with the accumulated plastic strain
    /// `plastic_strain` ([`DruckerPrager::pq_surface`]).
    pub fn pq_surface(&self, plastic_strain: f64) -> super::PqSurface {
        self.model().pq_surface(plastic_strain)
    }
    /// The friction coefficient a steadily shearing layer of the cohesionless material
    /// mobilises, τ/σ_n = 3 α_φ (ψ = 0; the flowing cone's α_φ with the start–stop match):
    /// slopes steeper than its arctangent keep flowing.
    pub fn steady_shear_friction(&self) -> f64 {
        let a = self.model().alpha_phi as f64;
        3.0 * match self.friction_match {
            FrictionMatch::StartStop => flowing_alpha(a),
            _ => a,
        }
    }
    pub fn model(&self) -> DruckerPrager {
        let fm = self.friction_match;
        let t = self.friction_angle.to_radians().tan();
        let alpha_phi = fm.alpha(t);
        let k_c = fm.k_c(self.cohesion, t);
        let apex = if alpha_phi > 0.0 {
            k_c / alpha_phi
        } else if k_c == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        let elastic = self.elastic().model();
        let alpha_psi = fm.alpha(self.dilatancy_angle.to_radians().tan());
        let inv_hardening =
            1.0 / (elastic.g as f64 + 9.0 * alpha_phi * alpha_psi * elastic.k as f64);
        let widening = (fm == FrictionMatch::StartStop).then(|| Widening {
            alpha: (flowing_alpha(alpha_phi) - alpha_phi) as Real,
            per_strain: (1.0 / FLOWING_STRAIN) as Real,
        });
        DruckerPrager {
            widening,
            mu_i: self
                .mu_i
                .map(|m| m.model(self.friction_angle, self.density, fm)),
            elastic,
            alpha_phi: alpha_phi as Real,
            alpha_psi: alpha_psi as Real,
            k_c: k_c as Real,
            apex: apex as Real,
            inv_hardening: inv_hardening as Real,
            packed_specific_volume: (1.0 / self.density) as Real,
        }
    }
}

/// The Drucker–Prager model with its Eq. 13 constants and the apex value of I1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerPrager {
    pub elastic: Elastic,
    pub alpha_phi: Real,
    pub alpha_psi: Real,
    pub k_c: Real,
    /// The largest I1 the material carries (the cone's apex; 0 for cohesionless sand).
    pub apex: Real,
    /// 1/(G + 9 α_φ α_ψ K), the denominator of Eq. 15.
    pub inv_hardening: Real,
    /// Rate-dependent friction: α_φ, the denominator and the apex per particle.
    pub mu_i: Option<MuI>,
    /// 1/ρ (m³/kg): the packed volume per unit mass.
    pub packed_specific_volume: Real,
    /// The cone's widening with the plastic strain ([`FrictionMatch::StartStop`]).
    pub widening: Option<Widening>,
}

/// How [`FrictionMatch::StartStop`]'s cone widens: α_φ grows by
/// `alpha · min(ε_p · per_strain, 1)` with the particle's accumulated plastic strain ε_p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Widening {
    /// α_f − α_s.
    pub alpha: Real,
    /// 1 / [`FLOWING_STRAIN`].
    pub per_strain: Real,
}

impl Widening {
    /// The cone's α_φ for the base `alpha` (Eq. 13's, or μ(I)'s) and the plastic strain
    /// `plastic_strain`, lane by lane.
    #[inline(always)]
    pub fn alpha_phi<T: Number>(&self, alpha: T, plastic_strain: T) -> T {
        alpha + (plastic_strain * self.per_strain).min(T::ONE) * self.alpha
    }
}

/// The accumulated equivalent plastic strain √(2/3 e_p : e_p) at which a particle with the
/// start–stop friction match is flowing, its cone widened to the steady-flow one (in simple
/// shear, a shear strain γ = √3 ε_p ≈ 1.7). Measured, not derived (docs/validation.md,
/// "The sand model behind the figures"): 0.5 let over-steep slopes harden before they
/// failed; 2 left heaps at φ = 45° 4–5° low.
pub const FLOWING_STRAIN: f64 = 1.0;

/// The steady-flow cone with the plane-strain angle of Eq. 13's cone α_s: sin φ_ps = 3 α_s and
/// 3 α_f = tan φ_ps, so α_f = α_s / √(1 − 9 α_s²) (finite: Eq. 13 keeps 3 α_s < √3/2).
pub fn flowing_alpha(alpha_s: f64) -> f64 {
    alpha_s / (1.0 - 9.0 * alpha_s * alpha_s).sqrt()
}

impl DruckerPrager {
    /// f = √J2 + α_φ I1 − k_c = 0 with I1 = −3p and √J2 = q/√3: q = √3 (k_c + 3 α_φ p), a cone
    /// whose apex is at p = −k_c / (3 α_φ) (the model's apex I1 = k_c/α_φ); α_φ is the cone's
    /// for a particle with the accumulated plastic strain `plastic_strain`.
    pub fn pq_surface(&self, plastic_strain: f64) -> super::PqSurface {
        let a = match self.widening {
            Some(w) => w.alpha_phi(self.alpha_phi, plastic_strain as Real),
            None => self.alpha_phi,
        };
        let (a, k) = (a as f64, self.k_c as f64);
        super::PqSurface {
            kind: "drucker_prager",
            label: "Drucker–Prager cone",
            slope: 3f64.sqrt() * 3.0 * a,
            intercept: 3f64.sqrt() * k,
            apex_p: if a > 0.0 {
                -k / (3.0 * a)
            } else {
                f64::NEG_INFINITY
            },
            lower: None,
        }
    }
    /// f(I1, J2) of Eq. 11.
    pub fn yield_function<S: SymTensor>(&self, stress: S) -> S::Scalar {
        stress.j2().sqrt() + stress.trace() * self.alpha_phi - self.k_c
    }
}

impl Constitutive for DruckerPrager {
    const PLASTIC: bool = true;
    #[inline(always)]
    fn update<S: SymTensor>(
        &self,
        stress: &mut S,
        rate: S,
        spin: S::Spin,
        plastic_strain: S::Scalar,
        dt: Real,
    ) -> StressUpdate<S::Scalar> {
        let zero = S::Scalar::ZERO;
        let e = &self.elastic;
        let g = e.g;
        let trial = e.trial(*stress, rate, spin, dt);
        let i1_trial = trial.trace();
        let s_trial = trial - S::iso(i1_trial * (1.0 / 3.0));
        let j2_trial = s_trial.ddot(s_trial) * 0.5;
        let sqrt_j2_trial = j2_trial.sqrt();
        // The cone: fixed, or widened by the flow's inertial number (μ(I)) and, with the
        // start–stop match, by the particle's plastic strain (the same in every lane when
        // both are off; the branch is on the model, not on a particle).
        let (alpha_phi, apex, inv_hardening) = match (&self.mu_i, &self.widening) {
            (None, None) => (
                S::Scalar::splat(self.alpha_phi),
                S::Scalar::splat(self.apex),
                S::Scalar::splat(self.inv_hardening),
            ),
            (mu_i, widening) => {
                let mut a = match mu_i {
                    None => S::Scalar::splat(self.alpha_phi),
                    Some(m) => m.alpha_phi(rate, i1_trial),
                };
                if let Some(w) = widening {
                    a = w.alpha_phi(a, plastic_strain);
                }
                let apex = if self.k_c == 0.0 {
                    S::Scalar::ZERO
                } else {
                    S::Scalar::splat(self.k_c) / a
                };
                // (no division for the usual ψ = 0, where the denominator is G)
                let inv = if self.alpha_psi == 0.0 {
                    S::Scalar::splat(self.inv_hardening)
                } else {
                    S::Scalar::ONE / (a * (9.0 * e.k * self.alpha_psi) + g)
                };
                (a, apex, inv)
            }
        };
        let f = sqrt_j2_trial + i1_trial * alpha_phi - self.k_c;
        // 1/√J2 is formed while the correction below is (the division is off the critical
        // path: at steady state every particle of a flowing sand body is plastic).
        let inv_sqrt_j2_trial =
            S::Scalar::select_gt(sqrt_j2_trial, zero, S::Scalar::ONE / sqrt_j2_trial, zero);
        // Plastic correction of Eq. 14 with the multiplier Δλ (radial in the deviatoric
        // plane), zero inside the cone. No branch: every lane does the same arithmetic.
        let dl = f.max(zero) * inv_hardening;
        // Safeguard 1 (tension cracking): shift the hydrostatic part back to the apex.
        let i1 = (i1_trial - dl * (9.0 * e.k * self.alpha_psi)).min(apex);
        // Below zero the return passes the cone's axis: only possible beyond the apex.
        // Safeguard 2: scale the deviatoric stress back onto the cone.
        let sqrt_j2 = (sqrt_j2_trial - dl * g)
            .max(zero)
            .min(-(i1 * alpha_phi) + self.k_c);
        let ratio = sqrt_j2 * inv_sqrt_j2_trial;
        // As corrections of the trial stress, so that an elastic step (ratio 1, I1 unchanged)
        // leaves it exactly.
        *stress = trial + s_trial.scaled(ratio - 1.0) + S::iso((i1 - i1_trial) * (1.0 / 3.0));
        // The deviator is scaled to ratio·√J2_trial (zero when the trial deviator is zero).
        let energy = e.energy_from_invariants(j2_trial * (ratio * ratio), i1 * (1.0 / 3.0));
        // The plastic work σ:Δε_p with Δε_p = C⁻¹:(σ_tr − σ): the deviator shrinks from s_tr to
        // ratio·s_tr, I1 moves from I1_tr to I1 (see [`StressUpdate::dissipation`]).
        // Zero inside the cone, where ratio is 1 only to rounding.
        let work = S::Scalar::select_gt(
            f,
            zero,
            j2_trial * (ratio - ratio * ratio) * (1.0 / g)
                + i1 * (i1_trial - i1) * (1.0 / (9.0 * e.k)),
            zero,
        );
        StressUpdate {
            plastic_strain: (sqrt_j2_trial - sqrt_j2_trial * ratio) * (1.0 / (SQRT_3 * g)),
            dissipation: work,
            energy,
        }
    }
    fn elastic(&self) -> &Elastic {
        &self.elastic
    }
    fn packed_specific_volume(&self) -> Option<Real> {
        Some(self.packed_specific_volume)
    }
}

impl super::Kind for DruckerPragerParams {
    const NAME: &'static str = "drucker_prager";
    const LABEL: &'static str = "Sand";
    const HINT: &'static str = "granular: Drucker–Prager";
    const FIELDS: &'static [&'static str] = &[
        "friction_angle",
        "dilatancy_angle",
        "cohesion",
        "youngs_modulus",
        "poisson_ratio",
        "density",
    ];
    type Model = DruckerPrager;
    fn preset() -> Self {
        DruckerPragerParams {
            youngs_modulus: 3.5e5,
            poisson_ratio: 0.3,
            density: 2200.0,
            friction_angle: 35.0,
            dilatancy_angle: 0.0,
            cohesion: 0.0,
            mu_i: None,
            volumetric_rate: VolumetricRate::Particle,
            friction_match: FrictionMatch::default(),
        }
    }
    fn elastic_params(&self) -> ElasticParams {
        self.elastic()
    }
    fn check(&self, path: &str) -> Result<()> {
        self.validate(path)
    }
    fn runtime(&self) -> DruckerPrager {
        self.model()
    }
    /// The cone of the runtime model, formed once ([`DruckerPrager::pq_surface`]).
    fn surface(&self) -> impl Fn(f64) -> super::PqSurface + 'static {
        let m = self.model();
        move |plastic_strain| m.pq_surface(plastic_strain)
    }
    /// The cone of friction angle φ, traced in plane strain at φ_ps, at rest on slopes up to
    /// [`FrictionMatch::repose_angle`].
    fn behaviour(&self) -> super::Behaviour {
        super::Behaviour::Granular(super::Friction {
            friction_angle: self.friction_angle,
            cohesion: self.cohesion,
            cone: Some(plane_strain_angle(self.friction_angle)),
            repose: self.friction_match.repose_angle(self.friction_angle),
        })
    }
    fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
        match name {
            "friction_angle" => Some(&mut self.friction_angle),
            "dilatancy_angle" => Some(&mut self.dilatancy_angle),
            "cohesion" => Some(&mut self.cohesion),
            _ => super::elastic_field(
                name,
                [
                    &mut self.youngs_modulus,
                    &mut self.poisson_ratio,
                    &mut self.density,
                ],
            ),
        }
    }
    fn volumetric_rate(&self) -> VolumetricRate {
        self.volumetric_rate
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_util::drive;
    use crate::math::Sym3;

    #[test]
    fn the_plane_strain_angle_is_below_phi_and_zero_at_zero() {
        assert_eq!(plane_strain_angle(0.0), 0.0);
        // tan 30° = 1/√3: α = (1/√3)/√13, 3α = √3/√13
        let expect = (3f64.sqrt() / 13f64.sqrt()).asin().to_degrees();
        assert!((plane_strain_angle(30.0) - expect).abs() < 1e-12);
        for phi in [10.0, 20.0, 30.0, 40.0] {
            assert!(plane_strain_angle(phi) < phi);
        }
    }

    fn sand(phi: f64, psi: f64, c: f64) -> DruckerPrager {
        matched(phi, psi, c, FrictionMatch::PlaneStrain)
    }

    fn matched(phi: f64, psi: f64, c: f64, friction_match: FrictionMatch) -> DruckerPrager {
        params(phi, psi, c, friction_match).model()
    }

    /// Sand of E = 350 kPa, ν = 0.3, 2200 kg/m³ without μ(I), each particle's own rate.
    fn params(phi: f64, psi: f64, c: f64, friction_match: FrictionMatch) -> DruckerPragerParams {
        DruckerPragerParams {
            youngs_modulus: 3.5e5,
            poisson_ratio: 0.3,
            density: 2200.0,
            friction_angle: phi,
            dilatancy_angle: psi,
            cohesion: c,
            mu_i: None,
            volumetric_rate: VolumetricRate::Particle,
            friction_match,
        }
    }

    fn confined(p: Real) -> Sym3 {
        Sym3::IDENTITY * -p
    }

    /// An at-rest stress: σ_yy = −100 Pa, σ_xx = σ_zz = K0 σ_yy with K0 = 0.5.
    const AT_REST: Sym3 = Sym3 {
        xx: -50.0,
        yy: -100.0,
        zz: -50.0,
        xy: 0.0,
        xz: 0.0,
        yz: 0.0,
    };

    /// [`AT_REST`] sheared at constant volume (v_x = y, γ̇ = 1 /s) for `steps` steps of 10⁻⁴ s:
    /// the stress, τ_xy/(−σ_yy) and the accumulated plastic strain.
    fn simple_shear(m: &DruckerPrager, steps: usize) -> (Sym3, f64, Real) {
        let (s, ep, _) = drive(
            m,
            AT_REST,
            [[0.0, 1.0, 0.0], [0.0; 3], [0.0; 3]],
            1e-4,
            steps,
            |_, _| {},
        );
        (s, (s.xy / -s.yy) as f64, ep)
    }

    #[test]
    fn eq13_constants() {
        let m = sand(30.0, 0.0, 1000.0);
        let t = (30f64).to_radians().tan();
        let d = (9.0 + 12.0 * t * t).sqrt();
        assert!((m.alpha_phi as f64 - t / d).abs() < 1e-6);
        assert!((m.k_c as f64 - 3000.0 / d).abs() < 1e-2);
        assert_eq!(m.alpha_psi, 0.0);
    }

    /// The steady-flow match: α = tan θ / 3 and k_c = c, so that √J2 = c + p tan φ on the cone.
    #[test]
    fn steady_flow_constants() {
        let m = matched(30.0, 10.0, 1000.0, FrictionMatch::SteadyFlow);
        let t = |a: f64| a.to_radians().tan();
        assert!((m.alpha_phi as f64 - t(30.0) / 3.0).abs() < 1e-6);
        assert!((m.alpha_psi as f64 - t(10.0) / 3.0).abs() < 1e-6);
        assert!((m.k_c as f64 - 1000.0).abs() < 1e-3);
        // the apex, where √J2 = 0: I1 = k_c / α_φ = 3c / tan φ
        assert!((m.apex as f64 - 3000.0 / t(30.0)).abs() < 1e-2 * m.apex as f64);
    }

    /// Simple shear at constant volume (v_x = γ̇ y) of cohesionless sand with ψ = 0, from an
    /// at-rest stress σ_yy = −p0, σ_xx = σ_zz = K0 σ_yy (K0 = 0.5) to a shear strain of 1. The
    /// plastic flow is along the deviator s, so every deviatoric component but s_xy relaxes
    /// away (to O(τ/G), which the Jaumann spin keeps) at a constant pressure, and the shear
    /// plane carries τ_xy/(−σ_yy) = √J2/p = 3 α_φ: a layer flowing down a slope stops below
    /// θ* = atan(3 α_φ). By Eq. 13, 3 α_φ = sin φ_ps, well below tan φ (θ* = 18.6°, 26.9°, 33.2°
    /// for φ = 20°, 32°, 45°); by the steady-flow match it is tan φ.
    #[test]
    fn steady_simple_shear_mobilises_three_alpha_phi() {
        let at_rest = AT_REST;
        let p = -at_rest.trace() / 3.0;
        let normal_deviators = |s: &Sym3| {
            let d = *s - Sym3::iso(s.trace() / 3.0);
            d.xx.abs().max(d.yy.abs()).max(d.zz.abs())
        };
        assert!(normal_deviators(&at_rest) > 0.4 * p);
        for phi in [20.0f64, 32.0, 45.0] {
            let tan_phi = phi.to_radians().tan();
            for fm in [FrictionMatch::PlaneStrain, FrictionMatch::SteadyFlow] {
                let m = matched(phi, 0.0, 0.0, fm);
                let (s, ratio, _) = simple_shear(&m, 10_000);
                let three_alpha = 3.0 * m.alpha_phi as f64;
                assert!(
                    (ratio / three_alpha - 1.0).abs() < 1e-3,
                    "φ = {phi}, {fm:?}: τ/σ_n = {ratio}, 3 α_φ = {three_alpha}"
                );
                assert!(normal_deviators(&s) < 1e-3 * p, "φ = {phi}, {fm:?}: {s:?}");
                assert!((-s.trace() / 3.0 - p).abs() < 1e-4 * p, "{s:?}");
                // the angle of repose a heap is judged against is where this layer stops
                let stop = ratio.atan().to_degrees();
                assert!(
                    (stop - fm.repose_angle(phi)).abs() < 0.05,
                    "φ = {phi}, {fm:?}: stops at {stop}°, repose angle {}°",
                    fm.repose_angle(phi)
                );
                match fm {
                    // the flowing layer holds the friction coefficient tan φ
                    FrictionMatch::SteadyFlow => assert!(
                        (ratio / tan_phi - 1.0).abs() < 1e-3,
                        "φ = {phi}: τ/σ_n = {ratio} vs tan φ = {tan_phi}"
                    ),
                    // Eq. 13's cone comes to rest 1.4° to 12° short of φ: the tolerance above tells them apart
                    FrictionMatch::PlaneStrain => {
                        let stop = ratio.atan().to_degrees();
                        let expected = [(20.0, 18.55), (32.0, 26.87), (45.0, 33.21)]
                            .iter()
                            .find(|e| e.0 == phi)
                            .unwrap()
                            .1;
                        assert!((stop - expected).abs() < 0.02, "φ = {phi}: θ* = {stop}");
                        assert!(ratio < 0.95 * tan_phi, "φ = {phi}: {ratio}");
                    }
                    // its own test below
                    FrictionMatch::StartStop => unreachable!("not in this loop"),
                }
            }
        }
    }

    /// The start–stop match. A particle without plastic strain has Eq. 13's cone: sheared
    /// under confinement p it first yields at √J2 = 3 α_s p, where the default does (a slope
    /// starts to fail at φ_ps = asin 3 α_s). Once it has flowed (ε_p ≥ [`FLOWING_STRAIN`]) its
    /// cone is the steady-flow one of the same angle: the steady simple shear of
    /// `steady_simple_shear_mobilises_three_alpha_phi`, carried to γ = 4, holds
    /// τ/σ_n = tan φ_ps, so a flowing layer stops at φ_ps too, not at atan(sin φ_ps).
    #[test]
    fn start_stop_starts_and_stops_at_the_plane_strain_angle() {
        use crate::material::test_util::rate_spin;
        for phi in [20.0f64, 32.0, 45.0] {
            let m = matched(phi, 0.0, 0.0, FrictionMatch::StartStop);
            let alpha_s = sand(phi, 0.0, 0.0).alpha_phi as f64;
            let sin_ps = 3.0 * alpha_s;
            let tan_ps = sin_ps / (1.0 - sin_ps * sin_ps).sqrt();
            // first yield under confinement
            let p = 1.0e3;
            let (rate, spin) = rate_spin([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]]);
            let (mut s, mut ep) = (confined(p), 0.0);
            let first_yield = loop {
                let u = m.update(&mut s, rate, spin, ep, 1e-5);
                // (an elastic step may report a plastic strain of round-off size)
                if u.plastic_strain > 1e-9 {
                    break s.j2().sqrt() as f64 / p as f64;
                }
                ep += u.plastic_strain;
                assert!(s.j2().sqrt() < p, "φ = {phi}: no yield");
            };
            assert!(
                (first_yield / sin_ps - 1.0).abs() < 1e-4,
                "φ = {phi}: first yield at √J2/p = {first_yield}, 3 α_s = {sin_ps}"
            );
            // steady simple shear from K0 = 0.5
            let (_, ratio, ep) = simple_shear(&m, 40_000);
            assert!(ep as f64 > FLOWING_STRAIN, "φ = {phi}: ε_p = {ep}");
            assert!(
                (ratio / tan_ps - 1.0).abs() < 1e-3,
                "φ = {phi}: τ/σ_n = {ratio}, tan φ_ps = {tan_ps}"
            );
            let stop = ratio.atan().to_degrees();
            let repose = FrictionMatch::StartStop.repose_angle(phi);
            assert!(
                (stop - repose).abs() < 0.05 && (repose - plane_strain_angle(phi)).abs() < 1e-9,
                "φ = {phi}: stops at {stop}°, repose angle {repose}°"
            );
            // Eq. 13 alone stops at atan(sin φ_ps): 6 % to 32 % less friction
            assert!(
                ratio > 1.05 * sin_ps,
                "φ = {phi}: {ratio} vs sin φ_ps {sin_ps}"
            );
        }
    }

    #[test]
    fn shear_under_confinement_yields_on_the_cone() {
        let m = sand(35.0, 0.0, 0.0);
        let p = 1.0e3;
        let a = 1.0;
        let (s, ep, diss) = drive(
            &m,
            confined(p),
            [[0.0, a, 0.0], [a, 0.0, 0.0], [0.0; 3]],
            1e-4,
            500,
            |_, s| {
                assert!(m.yield_function(*s) <= 1e-3 * p);
            },
        );
        // √J2 at failure = k_c − α_φ I1 = 3 α_φ p
        let tau = 3.0 * m.alpha_phi * p;
        assert!(
            (s.j2().sqrt() - tau).abs() < 1e-3 * tau,
            "{} vs {tau}",
            s.j2().sqrt()
        );
        // ψ = 0: no plastic volume change, so the pressure is unchanged by isochoric shear.
        assert!(
            (s.trace() / 3.0 + p).abs() < 1e-3 * p,
            "pressure changed: {}",
            -s.trace() / 3.0
        );
        assert!(ep > 0.0 && diss > 0.0);
    }

    /// With μ(I) a steady simple shear at rate γ̇ under pressure p flows on the cone of
    /// μ(I), I = γ̇ d/√(p/ρ): √J2 = 3 α_φ(I) p, above the rate-independent 3 α_φ p, and the
    /// faster the shear the higher; the pressure is unchanged (ψ = 0).
    #[test]
    fn mu_i_shear_flows_on_the_cone_of_its_inertial_number() {
        let p = 500.0;
        let mut params = params(32.0, 0.0, 0.0, FrictionMatch::PlaneStrain);
        let plain = params.model();
        params.mu_i = Some(MuIParams {
            grain_diameter: 1e-3,
        });
        let m = params.model();
        let law = m.mu_i.unwrap();
        let mut last = 3.0 * plain.alpha_phi * p;
        for gamma in [1.0, 10.0, 100.0] {
            let (s, _, _) = drive(
                &m,
                confined(p),
                [[0.0, gamma, 0.0], [0.0; 3], [0.0; 3]],
                2e-5,
                2000,
                |_, _| {},
            );
            let i = law.inertial_number(gamma, p);
            let mu = law.friction(i) as f64;
            let tau = 3.0 * p as f64 * mu / (9.0 + 12.0 * mu * mu).sqrt();
            let got = s.j2().sqrt() as f64;
            assert!(
                (got - tau).abs() < 1e-3 * tau,
                "γ̇ = {gamma}: {got} vs {tau}"
            );
            assert!(got > last as f64, "γ̇ = {gamma}: {got} not above {last}");
            last = got as Real;
            assert!((s.trace() / 3.0 + p).abs() < 1e-3 * p);
        }
        // at rest the cone is the rate-independent one
        let mut s = confined(p);
        let u = m.update(&mut s, Sym3::ZERO, Default::default(), 0.0, 1e-3);
        assert_eq!((s, u.plastic_strain), (confined(p), 0.0));
        let json = r#"{"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200,
            "friction_angle": 32, "mu_i": {"grain_diameter": -1}}"#;
        let bad: DruckerPragerParams = serde_json::from_str(json).unwrap();
        assert_eq!(
            bad.validate("bodies[0].material.drucker_prager")
                .unwrap_err()
                .to_string(),
            "bodies[0].material.drucker_prager.mu_i.grain_diameter = -1: must be in (0, 0.1] (m)"
        );
    }

    /// μ(I) takes the body's friction match: with the steady-flow match a steady simple shear
    /// under pressure p carries τ = μ(I) p.
    #[test]
    fn mu_i_takes_the_friction_match() {
        let p = 500.0;
        let params = DruckerPragerParams {
            mu_i: Some(MuIParams {
                grain_diameter: 1e-3,
            }),
            ..params(32.0, 0.0, 0.0, FrictionMatch::SteadyFlow)
        };
        let m = params.model();
        let law = m.mu_i.unwrap();
        let gamma = 10.0;
        let (s, _, _) = drive(
            &m,
            confined(p),
            [[0.0, gamma, 0.0], [0.0; 3], [0.0; 3]],
            2e-5,
            2000,
            |_, _| {},
        );
        let mu = law.friction(law.inertial_number(gamma, p));
        let tau = mu * p;
        assert!(mu > (32f64.to_radians().tan() + 0.01) as Real);
        assert!(
            (s.xy - tau).abs() < 1e-3 * tau,
            "τ = {} vs μ(I) p = {tau}",
            s.xy
        );
        // at rest: the steady-flow cone of tan φ
        assert!((law.alpha_phi(Sym3::ZERO, -3.0 * p) - m.alpha_phi).abs() < 1e-6);
    }

    /// The options read and write as `"volumetric_rate": "cell_average"` and
    /// `"friction_match": "steady_flow"`; the defaults are left out of a saved scene.
    #[test]
    fn the_volumetric_rate_option_round_trips() {
        let json = r#"{"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200,
            "friction_angle": 32, "volumetric_rate": "cell_average",
            "friction_match": "steady_flow"}"#;
        let mut p: DruckerPragerParams = serde_json::from_str(json).unwrap();
        assert_eq!(p.volumetric_rate, VolumetricRate::CellAverage);
        assert_eq!(p.friction_match, FrictionMatch::SteadyFlow);
        let text = serde_json::to_string(&p).unwrap();
        assert!(
            text.contains(r#""volumetric_rate":"cell_average""#)
                && text.contains(r#""friction_match":"steady_flow""#),
            "{text}"
        );
        assert_eq!(
            serde_json::from_str::<DruckerPragerParams>(&text).unwrap(),
            p
        );
        // the paper's Eq. 13 alone is written out; the default start–stop match is not
        p.friction_match = FrictionMatch::PlaneStrain;
        let text = serde_json::to_string(&p).unwrap();
        assert!(
            text.contains(r#""friction_match":"plane_strain""#),
            "{text}"
        );
        p.volumetric_rate = VolumetricRate::Particle;
        p.friction_match = FrictionMatch::StartStop;
        let text = serde_json::to_string(&p).unwrap();
        assert!(
            !text.contains("volumetric_rate") && !text.contains("friction_match"),
            "{text}"
        );
        let p: DruckerPragerParams = serde_json::from_str(&text).unwrap();
        assert_eq!(p.volumetric_rate, VolumetricRate::Particle);
        assert_eq!(p.friction_match, FrictionMatch::StartStop);
        let bad = json.replace("steady_flow", "steady");
        assert_eq!(
            serde_json::from_str::<DruckerPragerParams>(&bad)
                .unwrap_err()
                .to_string(),
            "unknown variant `steady`, expected one of `plane_strain`, `steady_flow`, `start_stop` at line 3 column 38"
        );
    }

    #[test]
    fn dilatancy_raises_the_pressure_of_constrained_shear() {
        let (p, a) = (1.0e3, 1.0);
        let l = [[0.0, a, 0.0], [a, 0.0, 0.0], [0.0; 3]];
        let (s0, _, _) = drive(&sand(35.0, 0.0, 0.0), confined(p), l, 1e-4, 500, |_, _| {});
        let (s1, _, _) = drive(&sand(35.0, 15.0, 0.0), confined(p), l, 1e-4, 500, |_, _| {});
        let (p0, p1) = (-s0.trace() / 3.0, -s1.trace() / 3.0);
        assert!((p0 - p).abs() < 1e-3 * p);
        assert!(
            p1 > 1.5 * p,
            "dilatant sand at constant volume must gain pressure: {p1}"
        );
        // and it stays on the cone
        let m = sand(35.0, 15.0, 0.0);
        assert!(m.yield_function(s1) <= 1e-3 * p1);
    }

    #[test]
    fn cohesionless_sand_carries_no_tension() {
        let m = sand(30.0, 0.0, 0.0);
        let r = 1.0;
        let (s, _, _) = drive(
            &m,
            confined(100.0),
            [[r, 0.0, 0.0], [0.0, r, 0.0], [0.0, 0.0, r]],
            1e-4,
            200,
            |_, s| {
                assert!(s.trace() <= 1e-6);
            },
        );
        assert!(s.components().iter().all(|c| c.abs() < 1e-3), "{s:?}");
    }

    #[test]
    fn cohesive_sand_stops_at_the_apex() {
        let m = sand(30.0, 5.0, 2000.0);
        let r = 1.0;
        // uniaxial tension pulls past the apex
        let (s, _, _) = drive(
            &m,
            Sym3::ZERO,
            [[r, 0.0, 0.0], [0.0; 3], [0.0; 3]],
            1e-4,
            300,
            |_, s| {
                assert!(s.trace() <= m.apex * 1.0001);
                assert!(m.yield_function(*s) <= 1e-3 * m.k_c);
            },
        );
        assert!(
            (s.trace() - m.apex).abs() < 1e-3 * m.apex,
            "{} vs apex {}",
            s.trace(),
            m.apex
        );
        assert!(s.j2().sqrt() < 1e-3 * m.k_c);
    }

    #[test]
    fn random_paths_stay_inside_the_cone() {
        let m = sand(40.0, 10.0, 500.0);
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) as f64 / (1u64 << 31) as f64 * 2.0 - 1.0) as Real
        };
        let mut s = confined(2000.0);
        for _ in 0..5000 {
            let l = [
                [rnd() - 0.3, rnd(), rnd()],
                [rnd(), rnd() - 0.3, rnd()],
                [rnd(), rnd(), rnd() - 0.3],
            ];
            let (rate, spin) = crate::material::test_util::rate_spin(l);
            let u = m.update(&mut s, rate, spin, 0.0, 2e-3);
            assert!(s.is_finite());
            assert!(
                m.yield_function(s) <= 1e-3 * (m.k_c + s.trace().abs()),
                "outside: {s:?}"
            );
            assert!(s.trace() <= m.apex + 1e-3);
            assert!(u.plastic_strain >= 0.0);
        }
    }

    #[test]
    fn validation() {
        let mut p = DruckerPragerParams {
            youngs_modulus: 1e5,
            poisson_ratio: 0.3,
            density: 2000.0,
            friction_angle: 90.0,
            dilatancy_angle: 0.0,
            cohesion: 0.0,
            mu_i: None,
            volumetric_rate: VolumetricRate::Particle,
            friction_match: FrictionMatch::PlaneStrain,
        };
        assert_eq!(
            p.validate("bodies[1].material.drucker_prager")
                .unwrap_err()
                .to_string(),
            "bodies[1].material.drucker_prager.friction_angle = 90: must be in [0, 90) (degrees)"
        );
        p.friction_angle = 30.0;
        p.dilatancy_angle = 31.0;
        assert!(
            p.validate("m")
                .unwrap_err()
                .to_string()
                .contains("m.dilatancy_angle = 31")
        );
        // the steady-flow cone, 3 α_φ = tan φ, stays below √3
        p.dilatancy_angle = 0.0;
        p.friction_match = FrictionMatch::SteadyFlow;
        p.friction_angle = 60.0;
        assert_eq!(
            p.validate("bodies[0].material.drucker_prager")
                .unwrap_err()
                .to_string(),
            "bodies[0].material.drucker_prager.friction_angle = 60: must be in [0, 60) (degrees, with the steady-flow friction match)"
        );
        p.friction_angle = 59.5;
        assert!(p.validate("m").is_ok());
        p.friction_match = FrictionMatch::PlaneStrain;
        p.friction_angle = 60.0;
        assert!(p.validate("m").is_ok());
        p.friction_angle = 30.0;
        p.cohesion = -1.0;
        assert!(
            p.validate("m")
                .unwrap_err()
                .to_string()
                .contains("m.cohesion = -1")
        );
    }
}
