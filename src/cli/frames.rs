//! Frame ranges (`1..=120`, `1..120`, `7`) and frame rates for `sinew eval` and `bake`:
//! parsed with checked arithmetic and bounded, whether they come from the command line or
//! from the rig's `frames` and `fps`.

/// The most frames one command evaluates.
pub const MAX_FRAMES: u64 = 10_000_000;

/// The largest frame number magnitude: 2^53, below which every whole frame is exact as the
/// `f64` the evaluation uses.
pub const MAX_FRAME: i64 = 1 << 53;

/// An inclusive range of whole frames, at most [`MAX_FRAMES`] long, within ±[`MAX_FRAME`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    /// First frame.
    pub start: i64,
    /// Last frame (inclusive).
    pub end: i64,
}

impl FrameRange {
    /// The range `start..=end`, or a message saying what is wrong with it (`what` names
    /// where it came from in that message).
    pub fn new(start: i64, end: i64, what: &str) -> Result<FrameRange, String> {
        if let Some(f) = [start, end].into_iter().find(|f| f.unsigned_abs() > MAX_FRAME as u64) {
            return Err(format!(
                "{what}: frame {f} is out of range; frames are whole numbers within ±{MAX_FRAME} (2^53)"
            ));
        }
        if end < start {
            return Err(format!(
                "{what}: the frame range {start}..={end} is empty; write it as START..=END with END >= START"
            ));
        }
        // Both within ±2^53: the difference cannot overflow.
        let count = (end - start) as u64 + 1;
        if count > MAX_FRAMES {
            return Err(format!(
                "{what}: {count} frames is too many; one run evaluates at most {MAX_FRAMES} frames"
            ));
        }
        Ok(FrameRange { start, end })
    }

    /// The frames in order.
    pub fn frames(&self) -> impl Iterator<Item = i64> {
        self.start..=self.end
    }

    /// Number of frames.
    pub fn len(&self) -> u64 {
        (self.end - self.start) as u64 + 1
    }

    /// Always false (a range has at least one frame); for clippy's `len` convention.
    pub fn is_empty(&self) -> bool {
        false
    }
}

/// Parses `A..=B`, `A..B` (B excluded) or a single frame `A`.
pub fn parse_frames(s: &str) -> Result<FrameRange, String> {
    let s = s.trim();
    let what = format!("--frames {s:?}");
    let num = |t: &str| -> Result<i64, String> {
        t.trim().parse::<i64>().map_err(|e| {
            let why = match e.kind() {
                std::num::IntErrorKind::PosOverflow | std::num::IntErrorKind::NegOverflow => {
                    format!("frames are within ±{MAX_FRAME}")
                }
                _ => "write whole frame numbers, e.g. 1..=24".to_string(),
            };
            format!("{what}: {t:?} is not a frame number ({why})")
        })
    };
    let (start, end) = if let Some((a, b)) = s.split_once("..=") {
        (num(a)?, num(b)?)
    } else if let Some((a, b)) = s.split_once("..") {
        let (a, b) = (num(a)?, num(b)?);
        if b <= a {
            return Err(format!(
                "{what}: the frame range is empty; write it as START..END with END > START"
            ));
        }
        (a, b - 1)
    } else {
        let f = num(s)?;
        (f, f)
    };
    FrameRange::new(start, end, &what)
}

/// The frames and frame rate of a run: `--frames` or else the rig's `frames`, `--fps` or
/// else the rig's `fps` or else 24. Refuses non-finite or non-positive rates and frame
/// ranges that [`FrameRange::new`] refuses.
pub fn resolve_timing(
    frames: Option<&str>,
    fps: Option<f64>,
    rig_frames: Option<(f64, f64)>,
    rig_fps: Option<f64>,
) -> Result<(FrameRange, f64), String> {
    let fps = match (fps, rig_fps) {
        (Some(f), _) => check_fps(f, "--fps")?,
        (None, Some(f)) => check_fps(f, "the rig's fps")?,
        (None, None) => 24.0,
    };
    let range = match (frames, rig_frames) {
        (Some(f), _) => parse_frames(f)?,
        (None, Some((a, b))) => {
            let whole = |x: f64| -> Result<i64, String> {
                let r = x.round();
                if r.is_finite() && r.abs() <= MAX_FRAME as f64 {
                    Ok(r as i64)
                } else {
                    Err(format!(
                        "the rig's frames ({a}, {b}) are out of range; frames are within ±{MAX_FRAME}"
                    ))
                }
            };
            FrameRange::new(whole(a)?, whole(b)?, "the rig's frames")?
        }
        (None, None) => return Err("give --frames, e.g. --frames 1..=24 (the rig sets no frame range)".into()),
    };
    Ok((range, fps))
}

pub(super) fn check_fps(fps: f64, what: &str) -> Result<f64, String> {
    if fps.is_finite() && fps > 0.0 {
        Ok(fps)
    } else {
        Err(format!("{what} {fps} must be a positive number of frames per second"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges() {
        assert_eq!(
            parse_frames("1..=3").unwrap().frames().collect::<Vec<_>>(),
            vec![1, 2, 3]
        );
        assert_eq!(parse_frames("1..3").unwrap().frames().collect::<Vec<_>>(), vec![1, 2]);
        assert_eq!(parse_frames("7").unwrap().frames().count(), 1);
        assert!(parse_frames("3..=1").is_err());
        assert!(parse_frames("1..1").is_err());
        assert!(parse_frames("a..=b").is_err());
    }

    /// Extreme bounds give errors, never an overflow (the arithmetic is checked) or an
    /// allocation.
    #[test]
    fn extreme_bounds_are_refused_with_a_reason() {
        for s in [
            "-4611686018427387904..=4611686018427387904",
            "-9223372036854775808..-9223372036854775808",
            "-9223372036854775808..=9223372036854775807",
            "9223372036854775807..=-9223372036854775808",
            "0..-9223372036854775808",
            "99999999999999999999",
            "9007199254740993",
        ] {
            let e = parse_frames(s).unwrap_err();
            assert!(
                e.contains(s.split("..").next().unwrap_or(s)) || e.contains("--frames"),
                "{s}: {e}"
            );
        }
        let e = parse_frames("0..=10000000").unwrap_err();
        assert!(e.contains("10000001 frames is too many"), "{e}");
        assert_eq!(parse_frames("1..=10000000").unwrap().len(), MAX_FRAMES);
        assert_eq!(parse_frames("-9007199254740992").unwrap().start, -MAX_FRAME);
    }

    #[test]
    fn timing_comes_from_the_flags_or_the_rig() {
        assert_eq!(resolve_timing(None, None, Some((1.0, 3.0)), None).unwrap().1, 24.0);
        let (r, fps) = resolve_timing(Some("2..=4"), Some(30.0), Some((1.0, 3.0)), Some(25.0)).unwrap();
        assert_eq!((r.start, r.end, fps), (2, 4, 30.0));
        assert!(resolve_timing(None, None, Some((1.0, f64::INFINITY)), None).is_err());
        assert!(resolve_timing(None, None, Some((0.0, 1e300)), None).is_err());
        assert!(resolve_timing(Some("1"), Some(0.0), None, None).is_err());
        assert!(resolve_timing(Some("1"), None, None, Some(f64::NAN)).is_err());
        assert!(resolve_timing(None, None, None, None).is_err());
    }
}
