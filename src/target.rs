//! Target sizes as people write them: `400x600`, `50%x100%`, `400x` (keep the height), a side
//! alone (`400`, `50%`). The command line's `--size`, `--width` and `--height` and the Python
//! package both read them here, so a size means the same and a typo gets the same message in
//! either. A percentage is of each input's side, so a target is resolved per input.

use crate::image::{Size, MAX_SIDE};

/// One side of a target: pixels, or a percentage of the input's side.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Side {
    Px(u32),
    Percent(f64),
}

/// A target as given: each side, or `None` to keep the input's.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Target {
    pub width: Option<Side>,
    pub height: Option<Side>,
}

/// A target that cannot be read, or that gives a size out of range for an input. The message
/// names the value and what is allowed; converts into [`crate::Error::InvalidOptions`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidTarget(pub String);

impl std::fmt::Display for InvalidTarget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InvalidTarget {}

/// Most a percentage may be: more gives above [`MAX_SIDE`] px from any input.
pub const MAX_PERCENT: f64 = MAX_SIDE as f64 * 100.0;

impl Side {
    /// `400` (px, 1 to [`MAX_SIDE`]) or `50%` (above 0 and at most [`MAX_PERCENT`]).
    pub fn parse(s: &str) -> Result<Side, InvalidTarget> {
        let t = s.trim();
        if let Some(num) = t.strip_suffix('%') {
            let p: f64 = num
                .trim()
                .parse()
                .map_err(|_| InvalidTarget(format!("'{s}' is not a percentage (e.g. 50%)")))?;
            if !(p > 0.0 && p <= MAX_PERCENT) {
                return Err(InvalidTarget(format!(
                    "'{s}' is out of range: a percentage of the input's side must be above 0% \
                     and at most {MAX_PERCENT}%"
                )));
            }
            return Ok(Side::Percent(p));
        }
        Side::parse_px(s).map(Side::Px)
    }

    /// A whole number of pixels, 1 to [`MAX_SIDE`].
    pub fn parse_px(s: &str) -> Result<u32, InvalidTarget> {
        let n: i64 = s.trim().parse().map_err(|_| {
            InvalidTarget(format!(
                "'{s}' is not a whole number of pixels or a percentage (e.g. 400 or 50%)"
            ))
        })?;
        Side::px(n)
    }

    /// `n` px, checked: 1 to [`MAX_SIDE`].
    pub fn px(n: i64) -> Result<u32, InvalidTarget> {
        if n < 1 || n > MAX_SIDE as i64 {
            return Err(InvalidTarget(format!(
                "{n} px is out of range: each side must be 1 to {MAX_SIDE}"
            )));
        }
        Ok(n as u32)
    }
}

impl Target {
    /// `--size` if given, else `--width` and `--height`.
    pub fn of(size: Option<Target>, width: Option<Side>, height: Option<Side>) -> Target {
        size.unwrap_or(Target { width, height })
    }

    /// `WxH` with each side in px or %, or one side left out (`400x`, `x300`); a lone
    /// percentage (`200%`) scales both sides, as ImageMagick's `-resize 200%` does.
    pub fn parse(s: &str) -> Result<Target, InvalidTarget> {
        if !s.contains(['x', 'X']) && s.trim().ends_with('%') {
            let side = Side::parse(s)?;
            return Ok(Target {
                width: Some(side),
                height: Some(side),
            });
        }
        let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| {
            InvalidTarget(format!(
                "'{s}' is not WIDTHxHEIGHT (e.g. 400x600, 50%x100%, 400x to keep the height) or \
                 a percentage of both sides (50%)"
            ))
        })?;
        let side = |v: &str| -> Result<Option<Side>, InvalidTarget> {
            if v.trim().is_empty() {
                Ok(None)
            } else {
                Side::parse(v).map(Some)
            }
        };
        let target = Target {
            width: side(w)?,
            height: side(h)?,
        };
        if target == Target::default() {
            return Err(InvalidTarget(format!(
                "'{s}' gives neither side: e.g. 400x600, or 400x to keep the height"
            )));
        }
        Ok(target)
    }

    /// The size for an input of size `from`; a percentage that gives more than [`MAX_SIDE`]
    /// px is refused, naming it.
    pub fn resolve(&self, from: Size) -> Result<Size, InvalidTarget> {
        let side = |s: Option<Side>, of: u32, name: &str| match s {
            None => Ok(of),
            Some(Side::Px(n)) => Ok(n),
            Some(Side::Percent(p)) => {
                let n = (of as f64 * p / 100.0).round().max(1.0);
                if n > MAX_SIDE as f64 {
                    return Err(InvalidTarget(format!(
                        "{p}% of the input's {name} ({of} px) is {n} px, out of range: each side \
                         must be 1 to {MAX_SIDE}"
                    )));
                }
                Ok(n as u32)
            }
        };
        let w = side(self.width, from.width, "width")?;
        let h = side(self.height, from.height, "height")?;
        Size::new(w, h).map_err(|e| InvalidTarget(e.to_string()))
    }

    /// The size when both sides are given in pixels, the same for every input.
    pub fn fixed(&self) -> Option<Size> {
        match (self.width, self.height) {
            (Some(Side::Px(w)), Some(Side::Px(h))) => Size::new(w, h).ok(),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_side_alone_and_one_side_left_out_resolve_per_input() {
        let from = Size::new(672, 480).unwrap();
        let half = Target {
            width: Some(Side::parse("50%").unwrap()),
            height: None,
        };
        assert_eq!(half.resolve(from), Ok(Size::new(336, 480).unwrap()));
        assert_eq!(half.fixed(), None);
        let t = Target::parse("x300").unwrap();
        assert_eq!(t.resolve(from), Ok(Size::new(672, 300).unwrap()));
        assert_eq!(
            Target::parse("400x600").unwrap().fixed(),
            Size::new(400, 600).ok()
        );
        assert!(Side::px(0).unwrap_err().0.contains("0 px is out of range"));
        assert!(Side::parse("0").unwrap_err().0.contains("out of range"));
        assert!(Target::parse("x").unwrap_err().0.contains("neither side"));
    }
}
