//! The bodies a front end drops or pours while a scene runs, recorded so that the session
//! replays: each drop, and each pour with how long it ran, with the simulated time it happened
//! at (counted from the start of the scene, or from the Clear that emptied it), kept in time
//! order; those given in advance (a shared link) land, or start, when the simulation reaches
//! their time.

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

/// One pour ([`super::Playground::start_pour`]): a spout held still over the floor, pouring a
/// preset sand from its time for its duration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PouredBody {
    /// Simulated time the pour started (s), on the drop clock.
    pub t: f64,
    /// The preset material's model (`drucker_prager` or `mohr_coulomb`).
    pub material: String,
    /// The volume poured per second Q (m³/s; in 2D m²/s per metre of depth).
    pub rate: f64,
    /// The centre of the spout's exit (m), where [`super::Playground::start_pour`] put it.
    pub spout: Vec<f64>,
    /// How long it poured (s); for the pour still running, how long it has run so far.
    pub duration: f64,
    /// When it started on the drop clock (s); absent while it is still to come.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub applied_at: Option<f64>,
}

impl PouredBody {
    /// A pour starting at clock time `t`, its figures rounded as a link records them (0.1 ms,
    /// three significant figures of the rate, 1 mm), so that a replay pours the same stream.
    pub fn rounded(t: f64, material: &str, rate: f64, spout: &[f64], duration: f64) -> Self {
        PouredBody {
            t: (t * 1e4).floor() / 1e4,
            material: material.to_string(),
            rate: format!("{rate:.2e}").parse().unwrap_or(rate),
            spout: spout
                .iter()
                .map(|&x| (x * 1e3).round() / 1e3 + 0.0)
                .collect(),
            duration,
            applied_at: None,
        }
    }
}

/// What a session adds to its scene, in the order it happened: the quality level it is
/// sampled at, parameters set, whether the scene's own bodies were cleared, and the drops and
/// pours after that. A front end keeps it (the page
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
    /// The pours, each with how long it ran.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pours: Vec<PouredBody>,
}

/// A drop or a pour that the solver refused, with its message.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Refused {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drop: Option<DroppedBody>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pour: Option<PouredBody>,
    pub error: String,
}

/// The pour running now: its entry in the session and its body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Running {
    pub record: usize,
    pub body: usize,
}

/// The drops and pours of a session and the clock they count on.
#[derive(Clone, Debug, Default)]
pub struct Drops {
    /// Sorted by time; those before `next` have landed.
    pub list: Vec<DroppedBody>,
    pub next: usize,
    /// Sorted by time; those before `next_pour` have started.
    pub pours: Vec<PouredBody>,
    pub next_pour: usize,
    /// The pour started by a front end that runs until it is stopped, if any.
    pub running: Option<Running>,
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
        self.pours.clear();
        self.next_pour = 0;
        self.running = None;
        self.origin = now;
    }

    /// Drops and pours to come, in time order, replacing any.
    pub fn schedule(&mut self, mut drops: Vec<DroppedBody>, mut pours: Vec<PouredBody>) {
        drops.sort_by(|a, b| a.t.total_cmp(&b.t));
        for d in &mut drops {
            d.applied_at = None;
        }
        self.list = drops;
        self.next = 0;
        pours.sort_by(|a, b| a.t.total_cmp(&b.t));
        for p in &mut pours {
            p.applied_at = None;
        }
        self.pours = pours;
        self.next_pour = 0;
        self.running = None;
    }

    /// The time on the drop clock of the next drop or pour to come.
    pub fn next_time(&self) -> Option<f64> {
        let drop = self.list.get(self.next).map(|d| d.t);
        let pour = self.pours.get(self.next_pour).map(|p| p.t);
        match (drop, pour) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Whether the next to come is a pour (it comes before the next drop, or no drop is left).
    pub fn pour_next(&self) -> bool {
        match (self.list.get(self.next), self.pours.get(self.next_pour)) {
            (Some(d), Some(p)) => p.t < d.t,
            (None, Some(_)) => true,
            _ => false,
        }
    }

    /// Records a pour started now on body `body`, running until it is stopped, before those
    /// still to come.
    pub fn record_pour(&mut self, mut pour: PouredBody, clock: f64, body: usize) {
        pour.applied_at = Some(clock);
        self.pours.insert(self.next_pour, pour);
        self.running = Some(Running {
            record: self.next_pour,
            body,
        });
        self.next_pour += 1;
    }

    /// Records a drop made now, before those still to come (their times are later).
    pub fn record(&mut self, mut drop: DroppedBody, clock: f64) {
        drop.applied_at = Some(clock);
        self.list.insert(self.next, drop);
        self.next += 1;
    }
}
