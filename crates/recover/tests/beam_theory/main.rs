//! Section forces of beam elements (report eq. 25: `section_forces`,
//! `harmonic_section_forces`, `ModalRecovery`) from the solution of the full
//! FE model, compared with closed forms of beam theory: cantilevers under
//! end loads (statics of the part beyond the cut; tip deflection
//! `P L^3 / (3 E I) + P L / (G A_s)`) and under uniform line loads, a simply
//! supported beam under a central load (`M = P x / 2`, `P L^3 / (48 E I)`),
//! a free beam accelerated as a rigid body by end loads (d'Alembert), and a
//! cantilever in harmonic motion (the Euler-Bernoulli solution with
//! `cosh, sinh, cos, sin` of `k x`, `k^4 = rho A Omega^2 / (E I)`). The sign
//! convention of `SectionForces` (internal force on the positive cut face,
//! rows `N Qy Qz T My Mz` in the element frame) is checked on its own.
//!
//! The beams, loads and closed forms the tests share are in `beams`; the
//! tests are in `statics` (end loads, line loads, the sign convention, a
//! simply supported beam), `dynamics` (d'Alembert, harmonic motion) and
//! `modal` (`ModalRecovery` of reduced bodies).

#[path = "../common/mod.rs"]
mod common;

mod beams;
mod dynamics;
mod modal;
mod statics;
