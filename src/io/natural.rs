//! Natural order of file names: `frame2` before `frame10`.
//!
//! Names are split into runs of ASCII digits and runs of everything else. Digit runs compare
//! as numbers (any length: no overflow, `007` equals `7` in value), other runs compare
//! case-insensitively. Ties are broken so that the order is total and deterministic: first
//! fewer leading zeros, then the plain byte order.

use std::cmp::Ordering;

/// Compares two names in natural order.
pub fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut x, mut y) = (a.as_bytes(), b.as_bytes());
    let mut tie = Ordering::Equal;
    loop {
        match (x.first(), y.first()) {
            (None, None) => return tie.then_with(|| a.cmp(b)),
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(cx), Some(cy)) if cx.is_ascii_digit() && cy.is_ascii_digit() => {
                let (dx, rx) = split_digits(x);
                let (dy, ry) = split_digits(y);
                let (zx, vx) = strip_zeros(dx);
                let (zy, vy) = strip_zeros(dy);
                let by_value = vx.len().cmp(&vy.len()).then_with(|| vx.cmp(vy));
                if by_value != Ordering::Equal {
                    return by_value;
                }
                if tie == Ordering::Equal {
                    tie = zx.cmp(&zy);
                }
                (x, y) = (rx, ry);
            }
            (Some(cx), Some(cy)) => {
                let by_char = cx.to_ascii_lowercase().cmp(&cy.to_ascii_lowercase());
                if by_char != Ordering::Equal {
                    return by_char;
                }
                (x, y) = (&x[1..], &y[1..]);
            }
        }
    }
}

fn split_digits(s: &[u8]) -> (&[u8], &[u8]) {
    let n = s.iter().take_while(|c| c.is_ascii_digit()).count();
    s.split_at(n)
}

/// (number of leading zeros, the digits after them).
fn strip_zeros(d: &[u8]) -> (usize, &[u8]) {
    let z = d.iter().take_while(|&&c| c == b'0').count();
    (z, &d[z..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_compare_by_value() {
        let mut names = vec![
            "frame10.png",
            "frame2.png",
            "frame1.png",
            "Frame3.png",
            "frame100.png",
            "frame20.png",
            "a.png",
            "frame.png",
        ];
        names.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(
            names,
            [
                "a.png",
                "frame.png",
                "frame1.png",
                "frame2.png",
                "Frame3.png",
                "frame10.png",
                "frame20.png",
                "frame100.png"
            ]
        );
    }

    #[test]
    fn padded_and_huge_numbers() {
        assert_eq!(natural_cmp("f-0009", "f-0010"), Ordering::Less);
        assert_eq!(natural_cmp("f9", "f0010"), Ordering::Less);
        assert_eq!(natural_cmp("f01", "f1"), Ordering::Greater);
        assert_eq!(natural_cmp("f1", "f1"), Ordering::Equal);
        let big = "x123456789012345678901234567890";
        let bigger = "x123456789012345678901234567891";
        assert_eq!(natural_cmp(big, bigger), Ordering::Less);
        assert_eq!(natural_cmp("2x10y", "2x9y"), Ordering::Greater);
    }

    #[test]
    fn order_is_total() {
        let names = [
            "a1", "A1", "a01", "a1b", "a", "b", "a10", "a2", "", "1", "01",
        ];
        for x in names {
            assert_eq!(natural_cmp(x, x), Ordering::Equal);
            for y in names {
                assert_eq!(natural_cmp(x, y), natural_cmp(y, x).reverse(), "{x} {y}");
                if x != y {
                    assert_ne!(natural_cmp(x, y), Ordering::Equal, "{x} {y}");
                }
            }
        }
    }
}
