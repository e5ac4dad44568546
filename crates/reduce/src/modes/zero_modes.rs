//! A free body's zero-frequency modes: its rigid-body modes (report eq.
//! 12-13), and those of a mechanism when there are more. A mechanism is an
//! error that names how many zero modes the body has, not only that some
//! are left over.

use crate::ReduceError;
use flexbody_linalg::eigen::leading_zeros;

/// How far the first elastic eigenvalue lies above the round-off zeros of
/// the rigid-body modes. A mechanism's zero comes out at their size (within
/// a factor 5 in the tests); a long planar beam of 2100 elements, whose
/// stiffness spans 13 decades, has its first elastic eigenvalue only 3.4e4
/// above its rigid zeros (27 and 73).
pub const ZERO_GAP: f64 = 1e3;

/// The first `nr` of the lowest eigenvalues `values` (ascending) are the
/// rigid-body modes (round-off zeros); the next must be clearly elastic,
/// else the body has a mechanism, and the error counts its zero modes with
/// [`count_zeros`]. Fewer than `nr + 1` values cannot tell.
pub(crate) fn check_zeros(
    values: &[f64],
    nr: usize,
    n: usize,
    lowest: impl FnMut(usize) -> Result<Vec<f64>, ReduceError>,
) -> Result<(), ReduceError> {
    if values.len() <= nr {
        return Ok(());
    }
    let rigid_max = values[..nr].iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let first = values[nr];
    let scale = values.last().copied().unwrap_or(0.0).abs();
    if first <= ZERO_GAP * rigid_max || first <= 1e-14 * scale {
        let zero = count_zeros(values.to_vec(), n, lowest)?;
        return Err(ReduceError::FreeMechanism {
            zero: zero.max(nr + 1),
            rigid: nr,
        });
    }
    Ok(())
}

/// How many of an `n`-DOF model's eigenvalues are round-off zeros, from its
/// lowest `values` (ascending): while all of them are zeros, `lowest(c)`
/// gives the lowest `c` (twice as many each time) until one is not, the
/// whole spectrum is known, or `lowest` gives no more.
pub(crate) fn count_zeros(
    mut values: Vec<f64>,
    n: usize,
    mut lowest: impl FnMut(usize) -> Result<Vec<f64>, ReduceError>,
) -> Result<usize, ReduceError> {
    loop {
        let top = values.last().copied().unwrap_or(0.0);
        let zero = leading_zeros(&values, top, ZERO_GAP);
        if zero < values.len() || values.len() >= n {
            return Ok(zero);
        }
        let more = lowest((2 * values.len()).clamp(1, n))?;
        if more.len() <= values.len() {
            return Ok(zero);
        }
        values = more;
    }
}

/// The error for a free body whose stiffness is singular on a statically
/// determinate support (`held`, which names the DOF): a mechanism, its
/// zero modes counted, when the body has more of them than its `nr`
/// rigid-body modes; else `held` itself (as also when they cannot be
/// counted). `lowest(c)` gives the lowest `c` eigenvalues of `n`.
pub(crate) fn mechanism_or(
    held: ReduceError,
    nr: usize,
    n: usize,
    mut lowest: impl FnMut(usize) -> Result<Vec<f64>, ReduceError>,
) -> ReduceError {
    let zero = lowest((nr + 1).min(n)).and_then(|values| count_zeros(values, n, &mut lowest));
    match zero {
        Ok(zero) if zero > nr => ReduceError::FreeMechanism { zero, rigid: nr },
        _ => held,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_zeros_known_asks_for_more_until_an_elastic_one() {
        // 12 zeros (two unconnected solids) in a spectrum of 100 values.
        let spectrum: Vec<f64> = (0..100)
            .map(|i| {
                if i < 12 {
                    1e-9 * (i as f64 - 6.0)
                } else {
                    1e6 * i as f64
                }
            })
            .collect();
        let mut asked = vec![];
        let lowest = |c: usize| {
            asked.push(c);
            Ok(spectrum[..c].to_vec())
        };
        let err = check_zeros(&spectrum[..7], 6, 100, lowest).unwrap_err();
        assert!(
            matches!(err, ReduceError::FreeMechanism { zero: 12, rigid: 6 }),
            "{err}"
        );
        assert_eq!(asked, vec![14]);
        // Six zeros and then elastic values: no mechanism, nothing asked.
        let fine: Vec<f64> = spectrum[6..].to_vec();
        let never = |_: usize| -> Result<Vec<f64>, ReduceError> { panic!("no mechanism") };
        assert!(check_zeros(&fine[..8], 6, 94, never).is_ok());
        // A spectrum of zeros alone: all of them.
        let zeros = [0.0; 5];
        assert_eq!(
            count_zeros(zeros[..2].to_vec(), 5, |c| Ok(zeros[..c].to_vec())).unwrap(),
            5
        );
    }
}
