//! Procedural characters with known skeletons, for tests, benchmarks and the
//! documentation's previews: unions of capsules (a capsule humanoid with bent or
//! straight limbs, a quadruped whose legs overlap in side view, a five-finger hand,
//! an X star) and a torus. Each [`Body`] carries, besides its mesh, the capsules it
//! was made of, grouped into a core (torso, palm, hub) and limbs, so a test can
//! check a skeleton against closed-form answers: whether a point is inside
//! ([`Body::contains`]), where each limb bends, and which vertices belong to which
//! limb ([`Body::vertex_owner`]).
//!
//! Conventions: Y up, characters face +Z, their left side is +X (the biped's axes);
//! symmetric bodies are mirror images across the plane x = 0, and a left limb's
//! mirror is the next limb in [`Body::limbs`].

use glam::{DVec3, Vec3};

use super::shapes::{capsule, merge, torus};
use sinew_core::data::Mesh;

/// A capsule: every point within `radius` of the segment `a`–`b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// One end of the axis.
    pub a: DVec3,
    /// The other end of the axis.
    pub b: DVec3,
    /// Radius.
    pub radius: f64,
}

impl Capsule {
    fn new(a: DVec3, b: DVec3, radius: f64) -> Self {
        Capsule { a, b, radius }
    }

    /// Distance from `p` to the capsule's axis segment.
    pub fn axis_distance(&self, p: DVec3) -> f64 {
        let ab = self.b - self.a;
        let l2 = ab.length_squared();
        let t = if l2 > 0.0 {
            ((p - self.a).dot(ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (self.a + ab * t).distance(p)
    }

    /// Whether `p` is inside the capsule by at least `margin`.
    pub fn contains(&self, p: DVec3, margin: f64) -> bool {
        self.axis_distance(p) <= self.radius - margin
    }

    /// Axis length.
    pub fn length(&self) -> f64 {
        self.a.distance(self.b)
    }
}

/// A limb: a chain of capsules from the body outward (each starting where the
/// previous one ends), and the points where a rigger puts its joints.
#[derive(Clone, Debug, PartialEq)]
pub struct Limb {
    /// A name for messages (`arm_L`, `index`, ...).
    pub name: String,
    /// The capsules, proximal first.
    pub capsules: Vec<Capsule>,
    /// Articulations: where the axis bends or the limb is thinnest (elbow, wrist...).
    pub articulations: Vec<DVec3>,
    /// The far end of the limb (its axis end plus the last radius).
    pub tip: DVec3,
}

impl Limb {
    /// Length along the axis from the first capsule's start to the tip.
    pub fn length(&self) -> f64 {
        let axis: f64 = self.capsules.iter().map(Capsule::length).sum();
        axis + self.capsules.last().map_or(0.0, |c| c.radius)
    }
}

/// Which part of a [`Body`] a mesh vertex was made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    /// The core (torso, palm, hub, ring).
    Core,
    /// Limb `i` of [`Body::limbs`].
    Limb(usize),
}

/// A procedural character: its mesh and the capsules it was built from.
#[derive(Clone, Debug)]
pub struct Body {
    /// The mesh (capsule surfaces merged without welding; they overlap).
    pub mesh: Mesh,
    /// Core capsules.
    pub core: Vec<Capsule>,
    /// Limbs; for symmetric bodies, left limbs are followed by their mirror images.
    pub limbs: Vec<Limb>,
    /// Per vertex: the part whose capsule made it.
    pub vertex_owner: Vec<Owner>,
    /// Whether the body is a mirror image of itself across x = 0.
    pub symmetric: bool,
}

impl Body {
    fn new(symmetric: bool) -> Self {
        Body {
            mesh: Mesh::default(),
            core: Vec::new(),
            limbs: Vec::new(),
            vertex_owner: Vec::new(),
            symmetric,
        }
    }

    fn add(&mut self, c: Capsule, owner: Owner, around: usize) {
        let m = capsule(c.a.as_vec3(), c.b.as_vec3(), c.radius as f32, around);
        self.vertex_owner.extend(std::iter::repeat_n(owner, m.positions.len()));
        self.mesh = merge(&[std::mem::take(&mut self.mesh), m]);
    }

    fn core_capsule(&mut self, c: Capsule, around: usize) {
        self.core.push(c);
        self.add(c, Owner::Core, around);
    }

    fn limb(&mut self, name: &str, capsules: Vec<Capsule>, articulations: Vec<DVec3>, around: usize) {
        let i = self.limbs.len();
        for c in &capsules {
            self.add(*c, Owner::Limb(i), around);
        }
        let last = capsules
            .last()
            .copied()
            .unwrap_or(Capsule::new(DVec3::ZERO, DVec3::ZERO, 0.0));
        let dir = (last.b - last.a).normalize_or_zero();
        self.limbs.push(Limb {
            name: name.to_string(),
            tip: last.b + dir * last.radius,
            capsules,
            articulations,
        });
    }

    /// A limb and, for a symmetric body, its mirror image across x = 0 (`_L` → `_R`).
    fn limb_pair(&mut self, name: &str, capsules: Vec<Capsule>, articulations: Vec<DVec3>, around: usize) {
        let m = |p: DVec3| DVec3::new(-p.x, p.y, p.z);
        let mirrored: Vec<Capsule> = capsules
            .iter()
            .map(|c| Capsule::new(m(c.a), m(c.b), c.radius))
            .collect();
        let arts: Vec<DVec3> = articulations.iter().map(|&p| m(p)).collect();
        self.limb(&format!("{name}_L"), capsules, articulations, around);
        self.limb(&format!("{name}_R"), mirrored, arts, around);
    }

    /// Whether `p` is inside some capsule by at least `margin`.
    pub fn contains(&self, p: DVec3, margin: f64) -> bool {
        self.core
            .iter()
            .chain(self.limbs.iter().flat_map(|l| l.capsules.iter()))
            .any(|c| c.contains(p, margin))
    }

    /// Whether vertex `v` lies on the visible surface: inside no capsule of another part.
    pub fn is_visible(&self, v: usize) -> bool {
        let p = self.mesh.positions[v].as_dvec3();
        let owner = self.vertex_owner[v];
        let margin = 1e-3 * self.size();
        let core_hides = owner != Owner::Core && self.core.iter().any(|c| c.contains(p, margin));
        let limb_hides = self
            .limbs
            .iter()
            .enumerate()
            .any(|(i, l)| owner != Owner::Limb(i) && l.capsules.iter().any(|c| c.contains(p, margin)));
        !core_hides && !limb_hides
    }

    /// The bounding-box diagonal of the mesh.
    pub fn size(&self) -> f64 {
        let (lo, hi) = self.mesh.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(l, h), p| (l.min(*p), h.max(*p)),
        );
        (hi - lo).as_dvec3().length()
    }
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A chain of capsules through `points` with one radius per segment.
fn chain(points: &[DVec3], radii: &[f64]) -> Vec<Capsule> {
    points
        .windows(2)
        .zip(radii)
        .map(|(w, &r)| Capsule::new(w[0], w[1], r))
        .collect()
}

/// A capsule humanoid about 1.82 tall in a T-pose (Y up, facing +Z). With `bent`, the
/// elbows bend 60° forward and the knees 40°; otherwise arms and legs are straight and
/// elbows, wrists, knees thin out (a thickness minimum is the only cue there). Feet
/// point forward (+Z) from the ankles in both. `around` sets the density (about
/// 3,000 vertices at 16). Limbs: `arm_L`, `arm_R`, `leg_L`, `leg_R`, `head`.
pub fn humanoid(bent: bool, around: usize) -> Body {
    let mut b = Body::new(true);
    let half = (around / 2).max(6);
    b.core_capsule(Capsule::new(v(0.0, 0.95, 0.0), v(0.0, 1.33, 0.0), 0.15), around);
    // The head: a neck and a round skull (the neck is a uniform thin stretch, not an
    // articulation with a known answer).
    b.limb(
        "head",
        chain(
            &[
                v(0.0, 1.42, 0.0),
                v(0.0, 1.62, 0.0),
                v(0.0, 1.70, 0.0),
                v(0.0, 1.72, 0.0),
            ],
            &[0.05, 0.05, 0.1],
        ),
        vec![],
        around,
    );
    let shoulder = v(0.17, 1.38, 0.0);
    if bent {
        let elbow = v(0.45, 1.38, 0.0);
        let t = 60f64.to_radians();
        let wrist = elbow + v(t.cos(), 0.0, t.sin()) * 0.26;
        let hand = wrist + v(t.cos(), 0.0, t.sin()) * 0.12;
        b.limb_pair(
            "arm",
            chain(&[shoulder, elbow, wrist, hand], &[0.05, 0.045, 0.04]),
            vec![elbow],
            half,
        );
    } else {
        // Straight: thin links at the elbow and the wrist, longer than the neighbouring
        // radii so the capsules' caps do not hide them.
        let (elbow, wrist) = (v(0.45, 1.38, 0.0), v(0.72, 1.38, 0.0));
        let g = v(0.048, 0.0, 0.0);
        b.limb_pair(
            "arm",
            chain(
                &[shoulder, elbow - g, elbow + g, wrist - g, wrist + g, v(0.85, 1.38, 0.0)],
                &[0.05, 0.03, 0.045, 0.026, 0.045],
            ),
            vec![elbow, wrist],
            half,
        );
    }
    let hip = v(0.09, 0.93, 0.0);
    if bent {
        // Thigh forward, shin back: the knee bends by 40°.
        let knee = hip + v(0.02, -0.44, 0.0).normalize() * 0.44 + v(0.0, 0.0, 0.08);
        let ankle = knee + (v(0.0, -0.42, -0.2).normalize() * 0.42);
        let ankle = v(ankle.x, 0.1, ankle.z.min(knee.z));
        b.limb_pair(
            "leg",
            chain(&[hip, knee, ankle, ankle + v(0.0, -0.04, 0.16)], &[0.07, 0.055, 0.045]),
            vec![knee, ankle],
            half,
        );
    } else {
        let (knee, ankle) = (v(0.11, 0.52, 0.0), v(0.12, 0.1, 0.0));
        let g = v(0.0, 0.065, 0.0);
        b.limb_pair(
            "leg",
            chain(
                &[hip, knee + g, knee - g, ankle + g, ankle, ankle + v(0.0, -0.04, 0.16)],
                &[0.07, 0.042, 0.058, 0.034, 0.045],
            ),
            vec![knee, ankle],
            half,
        );
    }
    b
}

/// A quadruped seen from the side, its legs overlapping in that view: a horizontal
/// body along Z (head at +Z), a neck and head, a tail, four legs 0.24 apart in X that
/// bend at the knee (front) and hock (back). About 4,000 vertices at `around` = 16.
/// Limbs: `front_L`, `front_R`, `hind_L`, `hind_R`, `head`, `tail`.
pub fn quadruped(around: usize) -> Body {
    let mut b = Body::new(true);
    let half = (around / 2).max(6);
    b.core_capsule(Capsule::new(v(0.0, 0.62, -0.45), v(0.0, 0.62, 0.45), 0.19), around);
    b.limb(
        "head",
        chain(
            &[v(0.0, 0.72, 0.55), v(0.0, 0.92, 0.72), v(0.0, 0.95, 0.98)],
            &[0.07, 0.09],
        ),
        vec![v(0.0, 0.92, 0.72)],
        half,
    );
    b.limb(
        "tail",
        chain(&[v(0.0, 0.66, -0.6), v(0.0, 0.78, -0.95)], &[0.04]),
        vec![],
        half,
    );
    let x = 0.12;
    let (fk, ff) = (v(x, 0.3, 0.44), v(x, 0.05, 0.38));
    b.limb_pair(
        "front",
        chain(&[v(x, 0.52, 0.36), fk, ff], &[0.055, 0.045]),
        vec![fk],
        half,
    );
    let (hk, hf) = (v(x, 0.28, -0.46), v(x, 0.05, -0.34));
    b.limb_pair(
        "hind",
        chain(&[v(x, 0.52, -0.36), hk, hf], &[0.06, 0.045]),
        vec![hk],
        half,
    );
    b
}

/// A right-ish hand (not symmetric): a palm of four merged capsules, four fingers of
/// three phalanges each curling 35° per knuckle toward -Z, a thumb of two phalanges
/// leaving the palm's side, and a wrist stub going down. About 5,000 vertices at
/// `around` = 12. Limbs: `thumb`, `index`, `middle`, `ring`, `pinky`, `wrist`.
pub fn hand(around: usize) -> Body {
    let mut b = Body::new(false);
    let xs = [-0.135, -0.045, 0.045, 0.135];
    for &x in &xs {
        b.core_capsule(Capsule::new(v(x * 0.8, 0.0, 0.0), v(x, 0.34, 0.0), 0.05), around);
    }
    let lengths = [
        [0.16, 0.1, 0.08],
        [0.18, 0.11, 0.08],
        [0.16, 0.1, 0.08],
        [0.12, 0.08, 0.07],
    ];
    let names = ["index", "middle", "ring", "pinky"];
    let curl = 35f64.to_radians();
    for (k, &x) in xs.iter().enumerate() {
        let mut p = v(x, 0.4, 0.0);
        let mut pts = vec![p];
        let mut arts = Vec::new();
        for (s, len) in lengths[k].iter().enumerate() {
            let a = curl * s as f64;
            p += v(0.0, a.cos(), -a.sin()) * *len;
            pts.push(p);
            if s < 2 {
                arts.push(p);
            }
        }
        b.limb(names[k], chain(&pts, &[0.03, 0.028, 0.026]), arts, around / 2 + 2);
    }
    let t0 = v(-0.17, 0.1, 0.0);
    let t1 = t0 + v(-0.16, 0.12, 0.0);
    let t2 = t1 + v(-0.03, 0.12, -0.02);
    let t3 = t2 + v(0.03, 0.07, -0.05);
    b.limb(
        "thumb",
        chain(&[t0, t1, t2, t3], &[0.045, 0.04, 0.035]),
        vec![t1, t2],
        around / 2 + 2,
    );
    b.limb(
        "wrist",
        chain(&[v(0.0, -0.02, 0.0), v(0.0, -0.22, 0.0)], &[0.08]),
        vec![],
        around,
    );
    b
}

/// An X: four capsule arms of length `arm` at ±45° in the XY plane around a ball.
/// Limbs: `arm_L` (+X, +Y), `arm_R`, `leg_L` (+X, -Y), `leg_R`.
pub fn x_star(arm: f64, radius: f64, around: usize) -> Body {
    let mut b = Body::new(true);
    b.core_capsule(Capsule::new(DVec3::ZERO, DVec3::ZERO, radius * 1.6), around);
    let d = std::f64::consts::FRAC_1_SQRT_2 * arm;
    b.limb_pair(
        "arm",
        vec![Capsule::new(DVec3::ZERO, v(d, d, 0.0), radius)],
        vec![],
        around,
    );
    b.limb_pair(
        "leg",
        vec![Capsule::new(DVec3::ZERO, v(d, -d, 0.0), radius)],
        vec![],
        around,
    );
    b
}

/// A torus around the Z axis (a ring has no limbs; the core is its tube, sampled as
/// 24 capsules).
pub fn ring(major: f64, minor: f64, around: usize, tube: usize) -> Body {
    let mut b = Body::new(true);
    b.mesh = torus(major as f32, minor as f32, around, tube);
    b.vertex_owner = vec![Owner::Core; b.mesh.positions.len()];
    let n = 24;
    for k in 0..n {
        let t0 = std::f64::consts::TAU * k as f64 / n as f64;
        let t1 = std::f64::consts::TAU * (k + 1) as f64 / n as f64;
        b.core.push(Capsule::new(
            v(t0.cos(), t0.sin(), 0.0) * major,
            v(t1.cos(), t1.sin(), 0.0) * major,
            minor,
        ));
    }
    b
}
