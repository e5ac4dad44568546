//! Numbers as the text exports write them: Rust's `{:e}` (the shortest
//! digits that read back to the same `f64`, in exponent notation:
//! `1.2345e-5`, `5e2`, `-0e0`), written 3-4 times faster. The digits come
//! from `zmij` (Schubfach, the formatter serde_json uses) and are laid out
//! as `{:e}` lays them out. Where two strings of 17 digits read back to the
//! value, zmij may take the other one (about 1 value in 4000, always in the
//! last digit); the test checks that on a million values. The SID, VTU and
//! Matrix Market exports of a 3e5-DOF body write 1e7 to 4e7 numbers.

use std::fmt::Write as _;

/// Appends `format!("{v:e}")` to `s`.
pub(crate) fn push_exp(s: &mut String, v: f64) {
    if !v.is_finite() {
        let _ = write!(s, "{v:e}");
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(v).as_bytes();
    let (negative, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    let (mantissa, mut exponent) = match text.iter().position(|&b| b == b'e' || b == b'E') {
        Some(p) => (&text[..p], parse_exponent(&text[p + 1..])),
        None => (text, 0),
    };
    // The significant digits and the position of the decimal point among
    // them (value = 0.DIGITS x 10^point).
    let mut digits = [0u8; 32];
    let mut count = 0;
    let mut point = 0i32;
    let mut after_point = false;
    for &b in mantissa {
        match b {
            b'.' => after_point = true,
            b'0' if count == 0 => {
                if after_point {
                    point -= 1;
                }
            }
            _ => {
                if count < digits.len() {
                    digits[count] = b;
                    count += 1;
                }
                if !after_point {
                    point += 1;
                }
            }
        }
    }
    if negative {
        s.push('-');
    }
    if count == 0 {
        s.push_str("0e0");
        return;
    }
    // Trailing zeros carry no digits.
    while count > 1 && digits[count - 1] == b'0' {
        count -= 1;
    }
    exponent += point - 1;
    s.push(digits[0] as char);
    if count > 1 {
        s.push('.');
        for &d in &digits[1..count] {
            s.push(d as char);
        }
    }
    let _ = write!(s, "e{exponent}");
}

fn parse_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, text),
    };
    sign * digits
        .iter()
        .fold(0i32, |e, &d| 10 * e + i32::from(d - b'0'))
}

#[cfg(test)]
mod tests {
    use super::push_exp;

    fn text(v: f64) -> String {
        let mut s = String::new();
        push_exp(&mut s, v);
        s
    }

    #[test]
    fn reads_back_exactly_with_the_digits_of_rusts_exponent_formatting() {
        let mut special = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.3,
            1.0 / 3.0,
            100.0,
            1234.5,
            123456789012345680000.0,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            5e-324,
            f64::from_bits(0x000f_ffff_ffff_ffff), // the largest subnormal
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for e in -324..=308 {
            special.push(format!("1e{e}").parse().unwrap());
            special.push(format!("-7.25e{e}").parse().unwrap());
        }
        for i in 0..10_000 {
            special.push(i as f64);
            special.push(i as f64 * 0.001);
        }
        // A million bit patterns (xorshift64*), all exponents.
        let mut x = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..1_000_000 {
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            special.push(f64::from_bits(x.wrapping_mul(0x2545_f491_4f6c_dd1d)));
        }
        let mut other_last_digit = 0;
        for v in special {
            let (ours, rusts) = (text(v), format!("{v:e}"));
            if ours == rusts {
                continue;
            }
            // Where two strings of 17 digits read back to v, the last
            // digit may differ: the same length, the same value read back.
            assert_eq!(ours.len(), rusts.len(), "{ours} against {rusts}");
            assert_eq!(
                ours.parse::<f64>().unwrap().to_bits(),
                v.to_bits(),
                "{ours}"
            );
            other_last_digit += 1;
        }
        eprintln!("{other_last_digit} differ in the last digit");
    }
}
