//! The `[study]` and `[frf]` tables.

use super::raw::RawFile;
use super::{FrfSpec, StudySpec};
use flexbody_io::{InputError, TomlSource};
use flexbody_reduce::Method;

/// The study's excitation frequencies and cases, checked.
pub(super) fn study(src: TomlSource<'_>, raw: &RawFile) -> Result<Option<StudySpec>, InputError> {
    let Some(s) = &raw.study else {
        return Ok(None);
    };
    for o in &s.omegas {
        let value = *o.get_ref();
        if !(value.is_finite() && value >= 0.0) {
            return Err(src.at(
                o,
                format!("study: omega {value} must be a finite frequency >= 0 (rad/s)"),
            ));
        }
    }
    for c in &s.cases {
        if let Some(f) = c.get_ref().fmax {
            if !(f.is_finite() && f > 0.0) || c.get_ref().modes > 0 {
                return Err(src.at(
                    c,
                    "study: fmax must be a positive frequency (Hz), given instead of modes",
                ));
            }
        }
        if c.get_ref().method == Method::Guyan && c.get_ref().modes > 0 {
            return Err(src.at(c, "study: the guyan method takes no eigenmodes (modes = 0)"));
        }
    }
    Ok(Some(StudySpec {
        omegas: s.omegas.iter().map(|o| *o.get_ref()).collect(),
        cases: s.cases.iter().map(|c| c.get_ref().clone()).collect(),
    }))
}

/// The most points of a `[frf]`: 10^7 solves of the coupled system.
pub const MAX_FRF_POINTS: usize = 10_000_000;

/// The frequency band and the number of points, checked.
pub(super) fn frf(src: TomlSource<'_>, raw: &RawFile) -> Result<Option<FrfSpec>, InputError> {
    let Some(f) = &raw.frf else {
        return Ok(None);
    };
    let r = f.get_ref();
    let [lo, hi] = r.band_hz;
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo && r.points >= 2) {
        return Err(src.at(
            f,
            "frf: band_hz = [low, high] with 0 <= low < high (Hz) and points >= 2",
        ));
    }
    if r.points > MAX_FRF_POINTS {
        return Err(src.at(
            f,
            format!(
                "frf: {} points, more than the {MAX_FRF_POINTS} a transfer function may have \
                 (each is a solve of the coupled system); take fewer points, or split the band \
                 into several runs",
                r.points
            ),
        ));
    }
    Ok(Some(FrfSpec {
        band_hz: r.band_hz,
        points: r.points,
    }))
}
