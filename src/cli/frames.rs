//! Parsing of frame ranges (`1..=120`, `1..120`, `7`) for `sinew eval` and `bake`.

/// An inclusive range of whole frames with a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    /// First frame.
    pub start: i64,
    /// Last frame (inclusive).
    pub end: i64,
}

impl FrameRange {
    /// The frames in order.
    pub fn frames(&self) -> impl Iterator<Item = i64> {
        self.start..=self.end
    }
}

/// Parses `A..=B`, `A..B` (B excluded) or a single frame `A`.
pub fn parse_frames(s: &str) -> Result<FrameRange, String> {
    let s = s.trim();
    let num = |t: &str| -> Result<i64, String> {
        t.trim()
            .parse::<i64>()
            .map_err(|_| format!("{t:?} is not a whole frame number"))
    };
    let (start, end) = if let Some((a, b)) = s.split_once("..=") {
        (num(a)?, num(b)?)
    } else if let Some((a, b)) = s.split_once("..") {
        (num(a)?, num(b)? - 1)
    } else {
        let f = num(s)?;
        (f, f)
    };
    if end < start {
        return Err(format!(
            "frame range {s:?} is empty; write it as START..=END with END >= START"
        ));
    }
    if end - start > 10_000_000 {
        return Err(format!("frame range {s:?} is too long (over ten million frames)"));
    }
    Ok(FrameRange { start, end })
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
        assert!(parse_frames("a..=b").is_err());
    }
}
