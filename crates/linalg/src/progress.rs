//! A progress hook for long computations (ordering, factorisations, Lanczos
//! iterations, block solves), so that a terminal front end can show where a
//! large model is. The kernels call [`Progress::report`]; the default does
//! nothing.
//!
//! Kernels take a `&dyn Progress` argument, handed down from the caller
//! that owns the display (the CLI's terminal bar or stage log); there is no
//! process-wide hook.

/// A stage of a long computation.
#[derive(Clone, Debug, PartialEq)]
pub enum Stage {
    /// Fill-reducing ordering and symbolic analysis of an `n`-equation matrix.
    Ordering { equations: usize },
    /// Symbolic analysis done: `factor_len` entries in `L`, `flops`
    /// floating-point operations per numeric factorisation.
    Analyzed {
        factor_len: usize,
        flops: f64,
        seconds: f64,
    },
    /// Numeric `LDL^T` of `K - shift M` started.
    Factorization { shift: f64 },
    /// A supernodal factorisation has done the fraction `done` of its
    /// work, `flops` floating-point operations in all (reported at each
    /// percent, from the threads that work on it).
    Factoring { done: f64, flops: f64 },
    /// Numeric factorisation finished.
    Factorized { shift: f64, seconds: f64 },
    /// A Lanczos expansion step: `solves` right-hand sides so far,
    /// `converged` of `wanted` eigenpairs converged, basis of `basis` vectors.
    Iteration {
        step: usize,
        solves: usize,
        converged: usize,
        wanted: usize,
        basis: usize,
    },
    /// The Lanczos iterations finished (after the Sturm check, which may
    /// continue them on its own factor): `solves`
    /// right-hand sides in `block_solves` sweeps through `L`, taking
    /// `solve_seconds`; `products` right-hand sides multiplied by `M`,
    /// taking `mass_seconds`; `seconds` in all.
    LanczosDone {
        solves: usize,
        block_solves: usize,
        solve_seconds: f64,
        products: usize,
        mass_seconds: f64,
        seconds: f64,
    },
    /// The Sturm check at `bound` counts `count` eigenvalues below it, of
    /// which the solver had found `found`; when `count > found` it continues.
    SturmCheck {
        bound: f64,
        count: usize,
        found: usize,
    },
    /// The `wanted` eigenpairs of an `equations`-equation model by the
    /// dense solver: too many for a Lanczos basis.
    DenseEigen { equations: usize, wanted: usize },
    /// A block solve of `columns` right-hand sides (static modes).
    Solves { columns: usize },
    /// The computation finished.
    Done { seconds: f64 },
}

/// Receives [`Stage`]s. Implementations must be cheap: `report` is called
/// once per Lanczos step and per percent of a factorisation.
pub trait Progress: Send + Sync {
    /// Called at each stage; the default ignores it.
    fn report(&self, stage: &Stage) {
        let _ = stage;
    }
}

/// The progress hook that ignores everything.
#[derive(Copy, Clone, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}
