//! Axis ranges, tick positions and tick labels.
//!
//! One number format per axis, chosen from the axis range:
//! - linear axes step by 1, 2 or 5 times a power of ten (four to eight
//!   steps over the data) and end on a tick;
//!   every label has the decimals the step needs, no more. Where the
//!   largest tick is at least 1e5, or the step below 1e-3, the labels are
//!   the values over a common power of ten `10^E` (`E` a multiple of 3, the
//!   engineering exponent) shown once beside the axis ([`Ticks::multiplier`]);
//! - integer axes (counts, such as a number of modes) have integer steps and
//!   integer labels;
//! - logarithmic axes have a tick at every decade (or every second, third..
//!   where they are many), each labelled as a power of ten.

/// How values map onto an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear, ticks at round decimal values.
    Linear,
    /// Linear, ticks at integers only.
    Integer,
    /// Logarithmic (base 10); only positive values are drawn.
    Log,
}

impl Scale {
    /// The name written into the SVG (`data-scale`).
    pub fn name(self) -> &'static str {
        match self {
            Scale::Linear => "linear",
            Scale::Integer => "integer",
            Scale::Log => "log",
        }
    }
}

/// The text of one tick label.
#[derive(Clone, Debug, PartialEq)]
pub enum TickText {
    /// A decimal number.
    Plain(String),
    /// `10^k`.
    Power(i32),
}

/// An axis's range and ticks.
#[derive(Clone, Debug, PartialEq)]
pub struct Ticks {
    pub scale: Scale,
    /// The axis runs from `range.0` to `range.1` (data units).
    pub range: (f64, f64),
    /// Labelled ticks: position (data units) and label.
    pub major: Vec<(f64, TickText)>,
    /// Unlabelled ticks (the 2..9 multiples between decades of a log axis).
    pub minor: Vec<f64>,
    /// `E` where the labels are the values over `10^E`.
    pub multiplier: Option<i32>,
}

impl Ticks {
    /// The ticks of an axis of `scale` that holds `(lo, hi)` (non-finite
    /// bounds, or non-positive ones on a log axis, give a default range).
    pub fn new(scale: Scale, (lo, hi): (f64, f64)) -> Ticks {
        match scale {
            Scale::Linear => linear(lo, hi),
            Scale::Integer => integer(lo, hi),
            Scale::Log => log(lo, hi),
        }
    }

    /// The ticks of a linear axis over exactly `(lo, hi)` (not extended to
    /// the next ticks), such as a phase axis over `[-pi, pi]`.
    pub fn exactly(lo: f64, hi: f64) -> Ticks {
        let mut t = linear(lo, hi);
        t.major.retain(|(v, _)| (lo..=hi).contains(v));
        t.range = (lo, hi);
        t
    }

    /// Where `v` lies along the axis: 0 at its start, 1 at its end; `None`
    /// where it cannot be drawn (not finite, or not positive on a log axis).
    pub fn fraction(&self, v: f64) -> Option<f64> {
        let (a, b) = self.range;
        let f = match self.scale {
            Scale::Log if v > 0.0 => (v.log10() - a.log10()) / (b.log10() - a.log10()),
            Scale::Log => return None,
            _ => (v - a) / (b - a),
        };
        f.is_finite().then_some(f)
    }
}

/// 1, 2 or 5 times a power of ten, near `raw`.
fn nice_step(raw: f64) -> f64 {
    let magnitude = 10f64.powf(raw.log10().floor());
    let f = raw / magnitude;
    let nice = if f < 1.5 {
        1.0
    } else if f < 3.5 {
        2.0
    } else if f < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * magnitude
}

/// `(lo, hi)` made finite and of non-zero width.
fn widened(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (-1.0, 1.0);
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) || hi == lo {
        let pad = (lo.abs() * 0.1).max(1e-12);
        return (lo - pad, hi + pad);
    }
    (lo, hi)
}

/// Four to eight steps at multiples of a round step, the range ending on ticks.
fn linear(lo: f64, hi: f64) -> Ticks {
    let (lo, hi) = widened(lo, hi);
    let step = nice_step((hi - lo) / 4.0);
    let (k0, k1) = ((lo / step + 1e-9).floor(), (hi / step - 1e-9).ceil());
    let values: Vec<f64> = (0..=(k1 - k0) as i64)
        .map(|k| (k0 + k as f64) * step + 0.0)
        .collect();
    let largest = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let step_exponent = (step.log10() + 1e-9).floor() as i32;
    let multiplier = (largest >= 1e5 || step_exponent < -3)
        .then(|| 3 * ((largest.log10() + 1e-9).floor() as i32).div_euclid(3));
    let scaled_exponent = step_exponent - multiplier.unwrap_or(0);
    let decimals = (-scaled_exponent).max(0) as usize;
    let scale = 10f64.powi(multiplier.unwrap_or(0));
    let major = values
        .iter()
        .map(|&v| {
            // `+ 0.0` turns -0 into 0.
            let text = format!("{:.decimals$}", v / scale + 0.0);
            (v, TickText::Plain(text))
        })
        .collect();
    Ticks {
        scale: Scale::Linear,
        range: (k0 * step, k1 * step),
        major,
        minor: vec![],
        multiplier,
    }
}

/// Integer ticks with a margin of half a step, so that points at the ends
/// lie inside the frame.
fn integer(lo: f64, hi: f64) -> Ticks {
    let (lo, hi) = if lo.is_finite() && hi.is_finite() && lo <= hi {
        (lo.round(), hi.round())
    } else {
        (0.0, 1.0)
    };
    let step = nice_step(((hi - lo) / 6.0).max(1.0)).max(1.0);
    let (a, b) = (lo - step / 2.0, hi + step / 2.0);
    let first = (a / step).ceil() as i64;
    let last = (b / step).floor() as i64;
    let major = (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            (v, TickText::Plain(format!("{v:.0}")))
        })
        .collect();
    Ticks {
        scale: Scale::Integer,
        range: (a, b),
        major,
        minor: vec![],
        multiplier: None,
    }
}

/// Whole decades around the positive values; at most about seven labels.
fn log(lo: f64, hi: f64) -> Ticks {
    let (lo, hi) = if lo > 0.0 && hi >= lo && hi.is_finite() {
        (lo, hi)
    } else {
        (1e-3, 1.0)
    };
    let d0 = (lo.log10() + 1e-9).floor() as i32;
    let mut d1 = (hi.log10() - 1e-9).ceil() as i32;
    if d1 <= d0 {
        d1 = d0 + 1;
    }
    let every = ((d1 - d0) as f64 / 7.0).ceil().max(1.0) as i32;
    let d0 = d0.div_euclid(every) * every;
    let d1 = d0 + (d1 - d0 + every - 1) / every * every;
    let major = (d0..=d1)
        .step_by(every as usize)
        .map(|d| (10f64.powi(d), TickText::Power(d)))
        .collect();
    let minor = if every == 1 {
        (d0..d1)
            .flat_map(|d| (2..10).map(move |m| m as f64 * 10f64.powi(d)))
            .collect()
    } else {
        vec![]
    };
    Ticks {
        scale: Scale::Log,
        range: (10f64.powi(d0), 10f64.powi(d1)),
        major,
        minor,
        multiplier: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(t: &Ticks) -> Vec<String> {
        t.major
            .iter()
            .map(|(_, l)| match l {
                TickText::Plain(s) => s.clone(),
                TickText::Power(k) => format!("1e{k}"),
            })
            .collect()
    }

    #[test]
    fn a_moderate_range_has_plain_labels_with_the_decimals_of_its_step() {
        let t = Ticks::new(Scale::Linear, (-0.013, 0.048));
        assert_eq!(t.multiplier, None);
        assert_eq!(labels(&t), ["-0.02", "0.00", "0.02", "0.04", "0.06"]);
        assert_eq!(t.range, (t.major[0].0, t.major.last().unwrap().0));
    }

    #[test]
    fn a_large_range_shares_one_engineering_exponent() {
        // The range of the report's bending moments in N m.
        let t = Ticks::new(Scale::Linear, (-2.1e6, 1.3e6));
        assert_eq!(t.multiplier, Some(6));
        assert_eq!(labels(&t), ["-3", "-2", "-1", "0", "1", "2"]);
        let small = Ticks::new(Scale::Linear, (-3.2e-5, 4.1e-5));
        assert_eq!(small.multiplier, Some(-6));
        assert_eq!(labels(&small), ["-40", "-20", "0", "20", "40", "60"]);
    }

    #[test]
    fn ten_thousand_is_written_without_decimals() {
        let t = Ticks::new(Scale::Linear, (0.0, 10000.0));
        assert_eq!(labels(&t), ["0", "2000", "4000", "6000", "8000", "10000"]);
    }

    #[test]
    fn a_range_that_starts_at_zero_starts_the_axis_at_zero() {
        let t = Ticks::new(Scale::Linear, (0.0, 2.5));
        assert_eq!(labels(&t), ["0.0", "0.5", "1.0", "1.5", "2.0", "2.5"]);
    }

    #[test]
    fn an_exact_range_keeps_its_ends_and_only_the_ticks_inside() {
        let pi = std::f64::consts::PI;
        let t = Ticks::exactly(-pi, pi);
        assert_eq!(t.range, (-pi, pi));
        assert_eq!(labels(&t), ["-2", "0", "2"]);
    }

    #[test]
    fn integer_axes_have_integer_ticks_even_over_a_short_range() {
        let t = Ticks::new(Scale::Integer, (5.0, 7.0));
        assert_eq!(labels(&t), ["5", "6", "7"]);
        assert!(t.range.0 < 5.0 && t.range.1 > 7.0);
        let wide = Ticks::new(Scale::Integer, (1.0, 60.0));
        assert!(wide.major.iter().all(|(v, _)| v.fract() == 0.0));
    }

    #[test]
    fn log_axes_cover_whole_decades() {
        let t = Ticks::new(Scale::Log, (3e-4, 2.0));
        assert_eq!(labels(&t), ["1e-4", "1e-3", "1e-2", "1e-1", "1e0", "1e1"]);
        assert_eq!(t.fraction(1e-4), Some(0.0));
        assert_eq!(t.fraction(0.0), None);
        let wide = Ticks::new(Scale::Log, (1e-17, 1.0));
        assert!(wide.major.len() <= 8, "{:?}", labels(&wide));
        assert!(wide.range.0 <= 1e-17 && wide.range.1 >= 1.0);
    }
}
