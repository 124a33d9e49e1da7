//! Maya's ramp attribute as a falloff curve (`falloffCurve[i]` with children
//! `falloffCurve_Position`, `falloffCurve_FloatValue`, `falloffCurve_Interp`; interpolation
//! `none` = 0, `linear` = 1, `smooth` = 2, `spline` = 3, the key's own interpolation used up
//! to the next key). Without keys the curve is Maya's default softMod falloff, 1 at the
//! centre to 0 at the radius with smooth interpolation: `1 − (3t² − 2t³)`.

/// Interpolation choices of a ramp key, by index.
pub const INTERPOLATIONS: [&str; 4] = ["none", "linear", "smooth", "spline"];

/// One ramp key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampKey {
    /// Position in [0, 1].
    pub position: f32,
    /// Value there.
    pub value: f32,
    /// Interpolation towards the next key (index into [`INTERPOLATIONS`]).
    pub interp: u8,
}

/// A ramp: keys sorted by position (empty = the default falloff).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ramp {
    /// The keys.
    pub keys: Vec<RampKey>,
}

#[inline]
fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

impl Ramp {
    /// Builds a ramp from unsorted keys (non-finite keys are an error naming the key).
    pub fn new(mut keys: Vec<RampKey>) -> Result<Self, String> {
        if let Some(k) = keys
            .iter()
            .position(|k| !k.position.is_finite() || !k.value.is_finite())
        {
            return Err(format!("falloffCurve key {k} is not finite"));
        }
        keys.sort_by(|a, b| a.position.total_cmp(&b.position));
        Ok(Ramp { keys })
    }

    /// The value at `t` (clamped to the first and last keys).
    #[inline]
    pub fn eval(&self, t: f32) -> f32 {
        let k = &self.keys;
        if k.is_empty() {
            let t = t.clamp(0.0, 1.0);
            return 1.0 - smooth(t);
        }
        let i = k.partition_point(|key| key.position <= t);
        if i == 0 {
            return k[0].value;
        }
        if i == k.len() {
            return k[i - 1].value;
        }
        let (a, b) = (k[i - 1], k[i]);
        let span = b.position - a.position;
        let u = if span > 0.0 { (t - a.position) / span } else { 1.0 };
        match a.interp {
            0 => a.value,
            1 => a.value + (b.value - a.value) * u,
            2 => a.value + (b.value - a.value) * smooth(u),
            _ => {
                // Catmull-Rom through the neighbours (missing end neighbours extrapolated
                // linearly, so evenly spaced linear data stays linear).
                let p0 = if i >= 2 {
                    k[i - 2].value
                } else {
                    2.0 * a.value - b.value
                };
                let p3 = k.get(i + 1).map_or(2.0 * b.value - a.value, |k| k.value);
                let (p1, p2) = (a.value, b.value);
                let u2 = u * u;
                0.5 * (2.0 * p1
                    + (p2 - p0) * u
                    + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u2
                    + (3.0 * p1 - p0 - 3.0 * p2 + p3) * u2 * u)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(position: f32, value: f32, interp: u8) -> RampKey {
        RampKey {
            position,
            value,
            interp,
        }
    }

    #[test]
    fn default_and_keyed_ramps() {
        let d = Ramp::default();
        assert_eq!(
            (d.eval(0.0), d.eval(0.5), d.eval(1.0), d.eval(2.0)),
            (1.0, 0.5, 0.0, 0.0)
        );
        let r = Ramp::new(vec![key(1.0, 0.0, 1), key(0.0, 1.0, 1)]).unwrap();
        assert_eq!(r.eval(0.25), 0.75);
        let r = Ramp::new(vec![key(0.0, 1.0, 0), key(0.5, 0.2, 2), key(1.0, 0.0, 3)]).unwrap();
        assert_eq!(r.eval(0.4), 1.0);
        assert_eq!(r.eval(0.75), 0.1);
        assert_eq!(r.eval(-1.0), 1.0);
        assert!(Ramp::new(vec![key(f32::NAN, 0.0, 0)]).is_err());
        // Catmull-Rom passes through its keys and is linear on evenly spaced linear data.
        let r = Ramp::new(vec![key(0.0, 0.0, 3), key(0.5, 0.5, 3), key(1.0, 1.0, 3)]).unwrap();
        assert!((r.eval(0.25) - 0.25).abs() < 1e-6 && (r.eval(0.8) - 0.8).abs() < 1e-6);
    }
}
