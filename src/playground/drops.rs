//! The bodies a front end drops while a scene runs, recorded so that the session replays:
//! each drop with the simulated time it happened at (counted from the start of the scene, or
//! from the Clear that emptied it), kept in time order; drops given in advance (a shared link)
//! land when the simulation reaches their time.

use serde::{Deserialize, Serialize};

/// One dropped body, as [`super::Playground::add_object`] takes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DroppedBody {
    /// Simulated time of the drop (s), on the drop clock.
    pub t: f64,
    /// `bunny`, `ball` or `box`.
    pub object: String,
    /// The preset material's model (a scene-file name of [`crate::material::KINDS`]).
    pub material: String,
    /// Height (m).
    pub size: f64,
    /// Centre (m).
    pub centre: Vec<f64>,
    /// Velocity (m/s).
    pub velocity: Vec<f64>,
    /// When it landed on the drop clock (s); absent while it is still to come.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub applied_at: Option<f64>,
}

impl DroppedBody {
    /// A drop at clock time `t` with its figures rounded as a link records them (0.1 ms, three
    /// significant figures of the size, 1 mm, 1 cm/s), so that a replay drops the same body.
    pub fn rounded(
        t: f64,
        object: &str,
        material: &str,
        size: f64,
        centre: &[f64],
        velocity: &[f64],
    ) -> Self {
        let round = |x: f64, per: f64| ((x * per).round() / per) + 0.0; // + 0.0: no −0
        DroppedBody {
            t: (t * 1e4).floor() / 1e4,
            object: object.to_string(),
            material: material.to_string(),
            size: format!("{size:.2e}").parse().unwrap_or(size),
            centre: centre.iter().map(|&x| round(x, 1e3)).collect(),
            velocity: velocity.iter().map(|&v| round(v, 1e2)).collect(),
            applied_at: None,
        }
    }
}

/// What a session adds to its scene, in the order it happened: the quality level it is
/// sampled at, parameters set, whether the scene's own bodies were cleared, and the drops after
/// that. A front end keeps it (the page
/// in its URL hash) and gives it back to [`super::Playground::replay`] to repeat the session.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Replay {
    /// The quality level (see [`super::QUALITIES`]); absent: the playground's as it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quality: Option<String>,
    /// `[name, value]` in the order they were last set.
    #[serde(default)]
    pub params: Vec<(String, f64)>,
    #[serde(default)]
    pub cleared: bool,
    #[serde(default)]
    pub drops: Vec<DroppedBody>,
}

/// A drop that the solver refused, with its message.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Refused {
    pub drop: DroppedBody,
    pub error: String,
}

/// The drops of a session and the clock they count on.
#[derive(Clone, Debug, Default)]
pub struct Drops {
    /// Sorted by time; those before `next` have landed.
    pub list: Vec<DroppedBody>,
    pub next: usize,
    /// The simulated time the drop clock counts from.
    pub origin: f64,
    /// The scene's own bodies were removed before the drops.
    pub cleared: bool,
}

impl Drops {
    /// Forgets every drop; the clock starts again at simulated time `now`.
    pub fn forget(&mut self, now: f64) {
        self.list.clear();
        self.next = 0;
        self.origin = now;
    }

    /// Drops to come, in time order, replacing any.
    pub fn schedule(&mut self, mut drops: Vec<DroppedBody>) {
        drops.sort_by(|a, b| a.t.total_cmp(&b.t));
        for d in &mut drops {
            d.applied_at = None;
        }
        self.list = drops;
        self.next = 0;
    }

    /// The time on the drop clock of the next drop to come.
    pub fn next_time(&self) -> Option<f64> {
        self.list.get(self.next).map(|d| d.t)
    }

    /// Records a drop made now, before those still to come (their times are later).
    pub fn record(&mut self, mut drop: DroppedBody, clock: f64) {
        drop.applied_at = Some(clock);
        self.list.insert(self.next, drop);
        self.next += 1;
    }
}
