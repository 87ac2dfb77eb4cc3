//! Constitutive models behind one small interface, [`Constitutive`], one model per file:
//! hypoelastic with the Jaumann rate ([`elastic`]), von Mises plasticity ([`von_mises`]),
//! non-associated Drucker–Prager ([`drucker_prager`]) and non-associated Mohr–Coulomb
//! ([`mohr_coulomb`]).
//!
//! [`Material`] holds the user-facing parameters (serde, SI units, validated); it builds the
//! runtime model with the derived constants. Each file's parameters type says what the rest
//! of the crate asks of a material ([`Kind`]: names, live parameters, preset, checks, yield
//! surface, behaviour and strength); adding a model is its file and its line in the `materials!` registration below.

pub mod drucker_prager;
pub mod elastic;
pub mod mohr_coulomb;
pub mod mu_i;
pub mod von_mises;

pub use drucker_prager::{
    DruckerPrager, DruckerPragerParams, FrictionMatch, VolumetricRate, plane_strain_angle,
};
pub use elastic::{Elastic, ElasticParams};
pub use mohr_coulomb::{MohrCoulomb, MohrCoulombParams};
pub use von_mises::{VonMises, VonMisesParams};

use crate::error::Result;
use crate::math::{Number, Real, SymTensor};
use serde::{Deserialize, Serialize};

/// The largest volume of a stressed granular particle, as a multiple of its packed volume
/// m/ρ: past its apex nothing resists an expansion, and a lone grain whose APIC affine velocity
/// stretches would otherwise inflate exponentially, and with it the wave speed at the body's
/// lowest density that sets everyone's time step. A packing loosens by a few per cent before
/// its grains part; twice the volume is far beyond that. It is also the density floor of a
/// granular body's wave speed ([`crate::sim::Body::wave_speed`]).
pub const LOOSEST: f64 = 2.0;

/// The largest volume of a parted granular particle (no compression, more than its packed
/// volume), as a multiple of its packed volume: it carries no stress, so its volume follows the
/// grains' spacing (a falling stream stretches tenfold) until it closes again; bounded only to
/// stay finite.
pub const PARTED_LOOSEST: f64 = 1000.0;

/// What a stress update did besides changing the stress (`T`: [`Real`], or [`crate::math::Real4`] for
/// four particles at once).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StressUpdate<T = Real> {
    /// Increment of the equivalent plastic strain √(2/3 e_p : e_p).
    pub plastic_strain: T,
    /// Energy removed by the plastic correction, per unit volume (J/m³): the plastic work
    /// σ_{n+1} : Δε_p of the returned stress over the plastic strain increment
    /// Δε_p = C⁻¹ : (σ_tr − σ_{n+1}). (The trial's stored energy minus the returned one's
    /// exceeds it by ½ Δε_p : C : Δε_p, which no force does as work: booked as dissipation it
    /// made the energy budget rise.)
    pub dissipation: T,
    /// The stored elastic energy per unit volume of the updated stress (J/m³), as
    /// [`Elastic::energy_density`] gives it, from the invariants the model already formed.
    pub energy: T,
}

impl<T: Number> StressUpdate<T> {
    /// An elastic update that leaves the energy density `energy`.
    #[inline(always)]
    pub fn elastic(energy: T) -> Self {
        StressUpdate {
            plastic_strain: T::ZERO,
            dissipation: T::ZERO,
            energy,
        }
    }
}

/// A constitutive model: advances a particle's Cauchy stress (tension positive) over one
/// time step, given the strain rate ε̇ = ½(∇v + ∇vᵀ), the spin ω = ½(∇v − ∇vᵀ) and the
/// particle's history, its accumulated equivalent plastic strain ε_p (which a model may
/// harden or soften with; the solver adds each update's increment to it). Generic over
/// the tensor type, whose components may be [`crate::math::Real4`]: the solver updates four particles per
/// call, so a model is written without branches (selects, `min`, `max`), the same arithmetic
/// in every lane.
pub trait Constitutive: Copy + Send + Sync + 'static {
    /// Whether the model can yield (elastic bodies skip all plastic work).
    const PLASTIC: bool;
    fn update<S: SymTensor>(
        &self,
        stress: &mut S,
        rate: S,
        spin: S::Spin,
        plastic_strain: S::Scalar,
        dt: Real,
    ) -> StressUpdate<S::Scalar>;
    /// The elastic part of the model (moduli and stored energy).
    fn elastic(&self) -> &Elastic;
    /// The volume per unit mass (m³/kg) of the material packed, 1/ρ, for a granular model
    /// whose grains part past its apex (sand); `None` for a solid, whose volume follows
    /// V̇ = V tr ε̇ without bound. The stress pass closes parted grains and bounds their
    /// volume with it ([`crate::step::stress`], [`LOOSEST`], [`PARTED_LOOSEST`]).
    fn packed_specific_volume(&self) -> Option<Real> {
        None
    }
}

/// How a material deforms, as far as the rest of the crate cares: the step's recipe
/// ([`crate::recipe::Recipe`]), the measures of a heap ([`crate::measure::deposits`]), the
/// lessons' questions and the page's Mohr plot all ask this, never which model it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Behaviour {
    /// Elastic or plastic solids: PIC, the stress updated last with the C¹ kernels, a bulk
    /// viscosity.
    Solid,
    /// Frictional, flowing materials (sand), with their strength: APIC with the C¹ kernels,
    /// the paper's α = 0.05, the stress updated first, no bulk viscosity; heaps are measured.
    Granular(Friction),
}

impl Behaviour {
    /// A frictional material's strength; `None` for a solid.
    pub fn friction(self) -> Option<Friction> {
        match self {
            Behaviour::Granular(f) => Some(f),
            Behaviour::Solid => None,
        }
    }
}

/// A frictional material's strength in a Mohr plane: the Mohr–Coulomb envelope
/// τ = c + σ_n tan φ (compression positive) of its friction angle and cohesion, and, for a
/// model whose yield surface is not that envelope, the line its surface traces in plane strain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Friction {
    /// φ (degrees).
    pub friction_angle: f64,
    /// c (Pa).
    pub cohesion: f64,
    /// For a Drucker–Prager cone, the angle φ_ps (degrees) of its trace in a plane-strain
    /// Mohr plane ([`plane_strain_angle`]); `None` when the yield surface is the
    /// Mohr–Coulomb envelope itself.
    #[serde(rename = "plane_strain_angle", skip_serializing_if = "Option::is_none")]
    pub cone: Option<f64>,
    /// The angle of repose (degrees): the steepest infinite slope on which a flowing layer of
    /// it stops. The layer shears in plane strain whatever the dimension, so a plane heap and
    /// a 3D cone are both drawn against it: φ_ps for the default start–stop cone
    /// ([`drucker_prager::FrictionMatch::repose_angle`]), Davis's angle for Mohr–Coulomb
    /// ([`davis`]), both from a flow that does not dilate in the layer's plane.
    #[serde(rename = "repose_angle")]
    pub repose: f64,
}

impl Friction {
    /// The angle (degrees) of the line the yield surface traces in a plane-strain Mohr plane:
    /// φ_ps for a cone, else φ.
    pub fn plane_strain_angle(&self) -> f64 {
        self.cone.unwrap_or(self.friction_angle)
    }
}

/// The strength a plane-strain shear band mobilises in a material of friction angle φ,
/// dilatancy ψ (degrees) and cohesion c (Pa), by Davis (1968): tan φ_d = sin φ cos ψ /
/// (1 − sin φ sin ψ) and c_d = c cos φ cos ψ / (1 − sin φ sin ψ), as (φ_d in degrees, c_d).
/// φ_d is φ itself only when ψ = φ (26.6° for φ = 30°, ψ = 0).
pub fn davis(friction_angle: f64, dilatancy_angle: f64, cohesion: f64) -> (f64, f64) {
    let (phi, psi) = (friction_angle.to_radians(), dilatancy_angle.to_radians());
    let d = 1.0 - phi.sin() * psi.sin();
    (
        (phi.sin() * psi.cos() / d).atan().to_degrees(),
        cohesion * phi.cos() * psi.cos() / d,
    )
}

/// What each material model provides, in its own file (its parameters type implements
/// it); the `materials!` registration lists it. The rest of the crate asks a material only this, through
/// [`Material`] and [`Model`].
pub trait Kind: Sized {
    /// The scene-file name (`{"<NAME>": {...}}`), the page's label and its hint.
    const NAME: &'static str;
    const LABEL: &'static str;
    const HINT: &'static str;
    /// Its live parameters, by their scene-file names, in the order the front ends show them
    /// (each described in [`crate::params`]).
    const FIELDS: &'static [&'static str];
    /// The runtime model.
    type Model: Constitutive + std::fmt::Debug + PartialEq;
    /// The material of new bodies on the page until a scene or a parameter says otherwise.
    fn preset() -> Self;
    /// E, ν and density.
    fn elastic_params(&self) -> ElasticParams;
    /// Checks every parameter; `path` names the material in error messages.
    fn check(&self, path: &str) -> Result<()>;
    /// The runtime model with its derived constants (valid parameters assumed).
    fn runtime(&self) -> Self::Model;
    /// The yield surface in p–q space ([`PqSurface`]) as a function of a particle's
    /// accumulated plastic strain (formed once, asked per particle).
    fn surface(&self) -> impl Fn(f64) -> PqSurface + 'static;
    /// Whether it flows like sand, with what strength, or deforms like a solid ([`Behaviour`]).
    fn behaviour(&self) -> Behaviour;
    /// The live parameter called `name` (one of [`Kind::FIELDS`]).
    fn field_mut(&mut self, name: &str) -> Option<&mut f64>;
    /// Which volumetric strain rate its stress update takes ([`VolumetricRate`]).
    fn volumetric_rate(&self) -> VolumetricRate {
        VolumetricRate::Particle
    }
}

/// E, ν or ρ, the live parameters every material has, by name.
pub(crate) fn elastic_field<'a>(name: &str, [e, nu, rho]: [&'a mut f64; 3]) -> Option<&'a mut f64> {
    match name {
        "youngs_modulus" => Some(e),
        "poisson_ratio" => Some(nu),
        "density" => Some(rho),
        _ => None,
    }
}

/// Code generic over the constitutive model, run with a body's model ([`Model::with`]).
pub trait WithModel {
    type Output;
    fn run<M: Constitutive>(self, model: &M) -> Self::Output;
}

/// A registered model as the front ends list it.
#[derive(Clone, Copy, Debug)]
pub struct KindInfo {
    pub name: &'static str,
    pub label: &'static str,
    pub hint: &'static str,
    pub fields: &'static [&'static str],
    pub preset: fn() -> Material,
}

/// Registers the material models: `Variant(Params)`, the variant's snake-case name being the
/// scene-file name. Makes [`Material`], [`Model`] and [`KINDS`], and dispatches to [`Kind`].
macro_rules! materials {
    ($($variant:ident($params:ty)),* $(,)?) => {
        /// The material of a body, as written in scene files: `{"<name>": {...}}` with the
        /// name of a registered model ([`KINDS`]).
        #[derive(Clone, Debug, PartialEq, Serialize)]
        #[serde(rename_all = "snake_case")]
        pub enum Material {
            $($variant($params),)*
        }

        /// Read by hand so that an object naming no model, or two, gets a message saying so.
        impl<'de> Deserialize<'de> for Material {
            fn deserialize<De: serde::Deserializer<'de>>(
                d: De,
            ) -> std::result::Result<Self, De::Error> {
                const NAMES: &[&str] = &[$(<$params as Kind>::NAME),*];
                struct Named;
                impl<'de> serde::de::Visitor<'de> for Named {
                    type Value = Material;
                    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                        write!(f, "an object naming one material model: {}", NAMES.join(", "))
                    }
                    fn visit_map<A: serde::de::MapAccess<'de>>(
                        self,
                        mut map: A,
                    ) -> std::result::Result<Material, A::Error> {
                        use serde::de::Error as _;
                        let Some(key) = map.next_key::<String>()? else {
                            return Err(A::Error::custom(format!(
                                "names no material model: it must name one of {}",
                                NAMES.join(", ")
                            )));
                        };
                        let material = $(if key == <$params as Kind>::NAME {
                            Material::$variant(map.next_value::<$params>()?)
                        } else)* {
                            return Err(A::Error::unknown_variant(&key, NAMES));
                        };
                        if let Some(second) = map.next_key::<String>()? {
                            return Err(A::Error::custom(format!(
                                "names two models, `{key}` and `{second}`: a material names exactly one of {}",
                                NAMES.join(", ")
                            )));
                        }
                        Ok(material)
                    }
                }
                d.deserialize_map(Named)
            }
        }

        /// The runtime form of a [`Material`], with derived constants.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Model {
            $($variant(<$params as Kind>::Model),)*
        }

        /// The registered models, in the order the page lists them.
        pub const KINDS: &[KindInfo] = &[$(KindInfo {
            name: <$params as Kind>::NAME,
            label: <$params as Kind>::LABEL,
            hint: <$params as Kind>::HINT,
            fields: <$params as Kind>::FIELDS,
            preset: || Material::$variant(<$params as Kind>::preset()),
        },)*];

        /// The registered models' places in [`KINDS`].
        #[allow(dead_code)]
        enum Index {
            $($variant,)*
        }

        impl Material {
            /// The model's place in [`KINDS`] (the order of registration).
            pub fn index(&self) -> usize {
                match self { $(Material::$variant(_) => Index::$variant as usize,)* }
            }
            /// The scene-file name of the model.
            pub fn kind(&self) -> &'static str {
                match self { $(Material::$variant(_) => <$params as Kind>::NAME,)* }
            }
            /// The elastic part of the parameters.
            pub fn elastic_params(&self) -> ElasticParams {
                match self { $(Material::$variant(m) => Kind::elastic_params(m),)* }
            }
            /// Checks every parameter; `path` names this material in error messages
            /// (e.g. `bodies[1].material`).
            pub fn validate(&self, path: &str) -> Result<()> {
                match self {
                    $(Material::$variant(m) => {
                        Kind::check(m, &format!("{path}.{}", <$params as Kind>::NAME))
                    })*
                }
            }
            /// Whether the material flows like sand, with what strength, or deforms like a
            /// solid ([`Behaviour`]).
            pub fn behaviour(&self) -> Behaviour {
                match self { $(Material::$variant(m) => Kind::behaviour(m),)* }
            }
            /// Where the yield surface of a particle with the accumulated plastic strain
            /// `plastic_strain` lies in p–q space (see [`PqSurface`]; only sand's start–stop
            /// cone depends on it).
            pub fn pq_surface(&self, plastic_strain: f64) -> PqSurface {
                self.pq_surfaces()(plastic_strain)
            }
            /// [`Material::pq_surface`] as a function of the plastic strain, for many
            /// particles.
            pub fn pq_surfaces(&self) -> Box<dyn Fn(f64) -> PqSurface> {
                match self { $(Material::$variant(m) => Box::new(Kind::surface(m)),)* }
            }
            /// Which volumetric strain rate the stress update takes ([`VolumetricRate`]).
            pub fn volumetric_rate(&self) -> VolumetricRate {
                match self { $(Material::$variant(m) => Kind::volumetric_rate(m),)* }
            }
            /// The live parameter called `name` (a scene-file field name), if the model has it.
            pub fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
                match self { $(Material::$variant(m) => Kind::field_mut(m, name),)* }
            }
            /// Builds the runtime model (valid parameters assumed).
            pub fn model(&self) -> Model {
                match self { $(Material::$variant(m) => Model::$variant(Kind::runtime(m)),)* }
            }
        }

        impl Model {
            /// Runs `f` with the model.
            #[inline(always)]
            pub fn with<W: WithModel>(&self, f: W) -> W::Output {
                match self { $(Model::$variant(m) => f.run(m),)* }
            }
            pub fn elastic(&self) -> &Elastic {
                match self { $(Model::$variant(m) => Constitutive::elastic(m),)* }
            }
            /// See [`Constitutive::packed_specific_volume`].
            pub fn packed_specific_volume(&self) -> Option<Real> {
                match self { $(Model::$variant(m) => Constitutive::packed_specific_volume(m),)* }
            }
        }
    };
}

materials! {
    Elastic(ElasticParams),
    VonMises(VonMisesParams),
    DruckerPrager(DruckerPragerParams),
    MohrCoulomb(MohrCoulombParams),
}

impl Material {
    /// An elastic material: Young's modulus E (Pa), Poisson ratio ν, density (kg/m³).
    pub fn elastic(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Material::Elastic(ElasticParams {
            youngs_modulus,
            poisson_ratio,
            density,
        })
    }
    /// A von Mises elastoplastic material with uniaxial yield stress σ_y (Pa).
    pub fn von_mises(
        youngs_modulus: f64,
        poisson_ratio: f64,
        density: f64,
        yield_stress: f64,
    ) -> Self {
        Material::VonMises(VonMisesParams {
            youngs_modulus,
            poisson_ratio,
            density,
            yield_stress,
        })
    }
    /// Sand: Drucker–Prager with friction angle φ and dilatancy angle ψ (degrees) and
    /// cohesion c (Pa).
    pub fn drucker_prager(
        youngs_modulus: f64,
        poisson_ratio: f64,
        density: f64,
        friction_angle: f64,
        dilatancy_angle: f64,
        cohesion: f64,
    ) -> Self {
        Material::DruckerPrager(DruckerPragerParams {
            youngs_modulus,
            poisson_ratio,
            density,
            friction_angle,
            dilatancy_angle,
            cohesion,
            mu_i: None,
            volumetric_rate: VolumetricRate::Particle,
            friction_match: FrictionMatch::default(),
        })
    }
    /// Mohr–Coulomb with friction angle φ and dilatancy angle ψ (degrees) and cohesion c
    /// (Pa), the Drucker–Prager sand's parameters.
    pub fn mohr_coulomb(
        youngs_modulus: f64,
        poisson_ratio: f64,
        density: f64,
        friction_angle: f64,
        dilatancy_angle: f64,
        cohesion: f64,
    ) -> Self {
        Material::MohrCoulomb(MohrCoulombParams {
            youngs_modulus,
            poisson_ratio,
            density,
            friction_angle,
            dilatancy_angle,
            cohesion,
        })
    }

    /// Density in kg/m³.
    pub fn density(&self) -> f64 {
        self.elastic_params().density
    }

    /// The dilatational wave speed √((K + 4G/3)/ρ) at the reference density, in m/s.
    pub fn wave_speed(&self) -> f64 {
        self.elastic_params().wave_speed()
    }
}

/// A model's yield surface in the meridian plane, for teaching views (the page's stress-path
/// plot and its yield colouring): pressure p = −tr σ / 3 (compression positive) against the
/// von Mises equivalent stress q = √(3 J2) (both Pa). The surface is the line
/// q = slope · p + intercept for p ≥ `apex_p`; an elastic model has none.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PqSurface {
    /// `none`, `von_mises` (a cylinder about the hydrostatic axis), `drucker_prager` (a cone) or
    /// `mohr_coulomb` (a hexagonal pyramid: the line is its triaxial compression meridian,
    /// `lower` its extension meridian).
    pub kind: &'static str,
    /// How a plot labels it.
    pub label: &'static str,
    pub slope: f64,
    pub intercept: f64,
    /// The apex's pressure (Pa): where the cone closes; very negative when there is none.
    #[serde(serialize_with = "finite_or_lowest")]
    pub apex_p: f64,
    /// A surface whose meridian depends on the Lode angle: its inner meridian
    /// (slope, intercept), below the line above; stresses at yield lie between the two.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lower: Option<(f64, f64)>,
}

fn finite_or_lowest<S: serde::Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_f64(if x.is_finite() { *x } else { -1e300 })
}

impl PqSurface {
    /// No yield surface (an elastic model).
    pub const NONE: PqSurface = PqSurface {
        kind: "none",
        label: "elastic: no yield surface",
        slope: 0.0,
        intercept: 0.0,
        apex_p: f64::NEG_INFINITY,
        lower: None,
    };

    /// Whether a stress state (p, q) lies on the surface (within 2 % of it; of its inner
    /// meridian if it has one) or beyond it, or past the apex. False without a surface.
    pub fn reached(&self, p: f64, q: f64) -> bool {
        if self.kind == PqSurface::NONE.kind {
            return false;
        }
        let (slope, intercept) = self.lower.unwrap_or((self.slope, self.intercept));
        let limit = slope * p + intercept;
        let scale = limit.abs().max(1e-3 * (q + p.abs())).max(1e-9);
        q >= limit - 0.02 * scale || p <= self.apex_p
    }
}

/// The (p, q) of a stress: p = −tr σ / 3, q = √(3 J2).
pub fn pq<S: SymTensor<Scalar = Real>>(stress: S) -> (f64, f64) {
    (
        -stress.trace() as f64 / 3.0,
        (3.0 * stress.j2() as f64).sqrt(),
    )
}

#[cfg(test)]
pub(crate) mod test_util {
    //! Drives a model through a prescribed, homogeneous velocity gradient.
    use super::*;
    use crate::math::{Mat3A as Mat3, Sym3, Vec3A};

    /// The strain rate and spin of a 3D velocity gradient given by rows.
    pub fn rate_spin(l: [[Real; 3]; 3]) -> (Sym3, [Real; 3]) {
        let m = Mat3::from_cols(
            Vec3A::new(l[0][0], l[1][0], l[2][0]),
            Vec3A::new(l[0][1], l[1][1], l[2][1]),
            Vec3A::new(l[0][2], l[1][2], l[2][2]),
        );
        <crate::math::D3 as crate::math::Dim>::rate_and_spin(m)
    }

    /// Runs `steps` steps of `dt` with a constant velocity gradient from `stress`, returning the
    /// final stress and the accumulated plastic strain and dissipation.
    pub fn drive<M: Constitutive>(
        model: &M,
        mut stress: Sym3,
        l: [[Real; 3]; 3],
        dt: Real,
        steps: usize,
        mut each: impl FnMut(usize, &Sym3),
    ) -> (Sym3, Real, Real) {
        let (rate, spin) = rate_spin(l);
        let (mut ep, mut diss) = (0.0, 0.0);
        for i in 0..steps {
            let u = model.update(&mut stress, rate, spin, ep, dt);
            ep += u.plastic_strain;
            diss += u.dissipation;
            each(i, &stress);
        }
        (stress, ep, diss)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{D2, Dim, Mat2, Sym2, Sym3, Vec2};

    /// The models report the stored energy of the stress they return: the same number
    /// `Elastic::energy_density` computes from the tensor, elastic and plastic steps alike.
    fn check_energy<M: Constitutive>(model: &M, steps: usize) {
        let elastic = *model.elastic();
        let check = |u: StressUpdate, e: Real, what: &str| {
            let scale = e.abs().max(1e-3);
            assert!(
                (u.energy - e).abs() <= 1e-4 * scale,
                "{what}: {} vs {e}",
                u.energy
            );
        };
        // 3D: a compression, then shear with spin (elastic, then yielding), then unloading in
        // tension (the Drucker–Prager apex).
        let mut s3 = Sym3::ZERO;
        let mut s2 = Sym2::ZERO;
        for i in 0..steps {
            let phase = (i * 3) / steps;
            let l = match phase {
                0 => [[-0.4, 0.0, 0.0], [0.0, -0.3, 0.0], [0.0, 0.0, -0.2]],
                1 => [[0.0, 0.9, 0.2], [-0.3, 0.0, 0.0], [0.1, 0.4, 0.0]],
                _ => [[0.6, 0.1, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.4]],
            };
            let (rate, spin) = test_util::rate_spin(l);
            let u = model.update(&mut s3, rate, spin, 0.0, 1e-3);
            check(u, elastic.energy_density(s3), "3D");
            let g = Mat2::from_cols(Vec2::new(l[0][0], l[1][0]), Vec2::new(l[0][1], l[1][1]));
            let (rate, spin) = D2::rate_and_spin(g);
            let u = model.update(&mut s2, rate, spin, 0.0, 1e-3);
            check(u, elastic.energy_density(s2), "2D");
        }
    }

    /// One model call on four particles in SIMD lanes gives, lane by lane, exactly what four
    /// scalar calls give (the same IEEE operations in the same order), in 2D and 3D, for
    /// lanes that stay elastic, yield, pass the apex, or hold no stress at all.
    fn check_lanes<M: Constitutive>(model: &M) {
        use crate::math::{Batch, LANES, Real4};
        let stress3: [Sym3; LANES] = [
            Sym3::ZERO,
            Sym3 {
                xx: -2e3,
                yy: -1e3,
                zz: -1.5e3,
                xy: 300.0,
                xz: -50.0,
                yz: 20.0,
            },
            Sym3 {
                xx: -5e3,
                yy: 4e3,
                zz: -1e3,
                xy: 2e3,
                xz: 900.0,
                yz: -700.0,
            },
            Sym3 {
                xx: 100.0,
                yy: 50.0,
                zz: 80.0,
                xy: 10.0,
                xz: 0.0,
                yz: 5.0,
            },
        ];
        let grads = [
            [[0.0; 3]; 3],
            [[-0.1, 0.2, 0.0], [0.05, -0.2, 0.1], [0.0, -0.3, 0.1]],
            [[0.3, 2.0, -0.4], [-1.0, -0.5, 0.7], [0.2, 0.1, 0.4]],
            [[0.5, 0.0, 0.0], [0.0, 0.4, 1e-12], [0.0, 0.0, 0.6]],
        ];
        let (rates, spins): (Vec<Sym3>, Vec<[Real; 3]>) =
            grads.iter().map(|&l| test_util::rate_spin(l)).unzip();
        let (rates, spins): ([Sym3; LANES], [[Real; 3]; LANES]) =
            (rates.try_into().unwrap(), spins.try_into().unwrap());
        let dt = 2e-3;
        // each lane with its own history (accumulated plastic strain)
        let history = [0.0, 0.05, 0.5, 2.0];
        let lanes_history = Real4::from_slice(&history);
        let mut lanes = Sym3::pack(&stress3);
        let u = model.update(
            &mut lanes,
            Sym3::pack(&rates),
            Sym3::pack_spin(&spins),
            lanes_history,
            dt,
        );
        let out = Sym3::unpack(lanes);
        for l in 0..LANES {
            let mut s = stress3[l];
            let v = model.update(&mut s, rates[l], spins[l], history[l], dt);
            assert_eq!(out[l], s, "3D lane {l}");
            let lane = |x: Real4| x.to_array()[l];
            assert_eq!(
                (lane(u.energy), lane(u.plastic_strain), lane(u.dissipation)),
                (v.energy, v.plastic_strain, v.dissipation),
                "3D lane {l}"
            );
        }
        // 2D: the in-plane parts of the same states.
        let stress2: [Sym2; LANES] = std::array::from_fn(|l| {
            let s = stress3[l];
            Sym2 {
                xx: s.xx,
                yy: s.yy,
                zz: s.zz,
                xy: s.xy,
            }
        });
        let rs2: Vec<(Sym2, Real)> = grads
            .iter()
            .map(|l| {
                D2::rate_and_spin(Mat2::from_cols(
                    Vec2::new(l[0][0], l[1][0]),
                    Vec2::new(l[0][1], l[1][1]),
                ))
            })
            .collect();
        let rates2: [Sym2; LANES] = std::array::from_fn(|l| rs2[l].0);
        let spins2: [Real; LANES] = std::array::from_fn(|l| rs2[l].1);
        let mut lanes = Sym2::pack(&stress2);
        let u = model.update(
            &mut lanes,
            Sym2::pack(&rates2),
            Sym2::pack_spin(&spins2),
            lanes_history,
            dt,
        );
        let out = Sym2::unpack(lanes);
        for l in 0..LANES {
            let mut s = stress2[l];
            let v = model.update(&mut s, rates2[l], spins2[l], history[l], dt);
            assert_eq!(out[l], s, "2D lane {l}");
            assert_eq!(u.energy.to_array()[l], v.energy, "2D lane {l}");
            assert_eq!(
                u.plastic_strain.to_array()[l],
                v.plastic_strain,
                "2D lane {l}"
            );
        }
    }

    #[test]
    fn four_lanes_update_exactly_as_four_scalar_calls() {
        let (e, nu, rho) = (1.0e6, 0.3, 1000.0);
        check_lanes(Material::elastic(e, nu, rho).model().elastic());
        let Model::VonMises(m) = Material::von_mises(e, nu, rho, 3.0e3).model() else {
            unreachable!()
        };
        check_lanes(&m);
        for c in [0.0, 500.0] {
            let Model::DruckerPrager(m) =
                Material::drucker_prager(e, nu, rho, 30.0, 10.0, c).model()
            else {
                unreachable!()
            };
            check_lanes(&m);
            let Model::MohrCoulomb(mc) = Material::mohr_coulomb(e, nu, rho, 30.0, 10.0, c).model()
            else {
                unreachable!()
            };
            check_lanes(&mc);
            // with the rate-dependent friction μ(I)
            let mut with = Material::drucker_prager(e, nu, rho, 30.0, 10.0, c);
            if let Material::DruckerPrager(p) = &mut with {
                p.mu_i = Some(mu_i::MuIParams {
                    grain_diameter: 1e-3,
                });
            }
            let Model::DruckerPrager(m) = with.model() else {
                unreachable!()
            };
            check_lanes(&m);
            check_energy(&m, 300);
            // with the start–stop cone, which widens with each lane's plastic strain, alone
            // and with μ(I)
            for mu_i in [
                None,
                Some(mu_i::MuIParams {
                    grain_diameter: 1e-3,
                }),
            ] {
                let mut with = Material::drucker_prager(e, nu, rho, 30.0, 10.0, c);
                if let Material::DruckerPrager(p) = &mut with {
                    p.friction_match = FrictionMatch::StartStop;
                    p.mu_i = mu_i;
                }
                let Model::DruckerPrager(m) = with.model() else {
                    unreachable!()
                };
                check_lanes(&m);
                check_energy(&m, 300);
            }
        }
    }

    /// Each model's p–q surface is where its own return mapping puts a yielding stress: a
    /// stress driven far into plastic flow lies on the line (and counts as reached), a small
    /// elastic one does not; the cone's apex is where Drucker–Prager's yield function is zero
    /// at zero shear.
    #[test]
    fn the_pq_surface_is_where_each_model_returns_a_yielding_stress() {
        let (e, nu, rho) = (1.0e6, 0.3, 1000.0);
        // Compression, then shear on top of it.
        let squeeze = [[-0.5, 0.0, 0.0], [0.0, -0.5, 0.0], [0.0, 0.0, -0.5]];
        let shear = [[0.0, 2.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let check = |m: Material, model: &dyn Fn(&mut Sym3, [[Real; 3]; 3])| {
            let surface = m.pq_surface(0.0);
            let mut s = Sym3::ZERO;
            model(&mut s, squeeze);
            let (p, q) = pq(s);
            assert!(p > 0.0 && !surface.reached(p, q + 1.0), "{m:?}: {p} {q}");
            for _ in 0..200 {
                model(&mut s, shear);
            }
            let (p, q) = pq(s);
            let on = surface.slope * p + surface.intercept;
            assert!(
                (q - on).abs() <= 2e-3 * on && surface.reached(p, q),
                "{m:?}: q = {q}, the surface {on} at p = {p}"
            );
        };
        let vm = Material::von_mises(e, nu, rho, 2.0e3);
        let Model::VonMises(v) = vm.model() else {
            unreachable!()
        };
        check(vm.clone(), &|s, l| {
            test_util::drive(&v, *s, l, 1e-3, 1, |_, x| *s = *x);
        });
        for (c, fm) in [0.0, 500.0].into_iter().flat_map(|c| {
            [
                FrictionMatch::PlaneStrain,
                FrictionMatch::SteadyFlow,
                // the cone at rest (each call here starts without plastic strain)
                FrictionMatch::StartStop,
            ]
            .map(|f| (c, f))
        }) {
            let mut dp = Material::drucker_prager(e, nu, rho, 30.0, 0.0, c);
            if let Material::DruckerPrager(p) = &mut dp {
                p.friction_match = fm;
            }
            let Model::DruckerPrager(d) = dp.model() else {
                unreachable!()
            };
            check(dp.clone(), &|s, l| {
                test_util::drive(&d, *s, l, 1e-3, 1, |_, x| *s = *x);
            });
            let apex = dp.pq_surface(0.0).apex_p;
            let at_apex = Sym3::iso(-apex as Real);
            assert!(
                d.yield_function(at_apex).abs() <= 1e-3 * (1.0 + c as Real),
                "{c}"
            );
        }
        let el = Material::elastic(e, nu, rho);
        assert_eq!(el.pq_surface(0.0), PqSurface::NONE);
        assert!(!PqSurface::NONE.reached(1e9, 1e9));
    }

    /// Every registered model's scene-file name is the one its material is written under, a
    /// preset reads back as itself and validates, and each live parameter it lists exists.
    #[test]
    fn every_registered_model_reads_and_writes_under_its_name() {
        for k in KINDS {
            let mut m = (k.preset)();
            assert_eq!(m.kind(), k.name);
            let text = serde_json::to_value(&m).unwrap();
            assert!(text.get(k.name).is_some(), "{text}");
            assert_eq!(serde_json::from_value::<Material>(text).unwrap(), m);
            m.validate("material").unwrap();
            for f in k.fields {
                assert!(m.field_mut(f).is_some(), "{}.{f}", k.name);
            }
            assert!(m.field_mut("colour").is_none());
        }
    }

    #[test]
    fn every_model_reports_the_energy_of_the_stress_it_returns() {
        let (e, nu, rho) = (1.0e6, 0.3, 1000.0);
        check_energy(Material::elastic(e, nu, rho).model().elastic(), 300);
        let Model::VonMises(m) = Material::von_mises(e, nu, rho, 2.0e3).model() else {
            unreachable!()
        };
        check_energy(&m, 300);
        for c in [0.0, 500.0] {
            let Model::DruckerPrager(m) =
                Material::drucker_prager(e, nu, rho, 30.0, 10.0, c).model()
            else {
                unreachable!()
            };
            check_energy(&m, 300);
            let Model::MohrCoulomb(m) = Material::mohr_coulomb(e, nu, rho, 30.0, 10.0, c).model()
            else {
                unreachable!()
            };
            check_energy(&m, 300);
        }
    }
}
