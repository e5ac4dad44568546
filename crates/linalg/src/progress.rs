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

/// One line describing a stage of the linear algebra, for a spinner or a
/// log: "factorising K - sigma M, sigma = 1.234e+04".
pub fn describe(stage: &Stage) -> String {
    match stage {
        Stage::Ordering { equations } => format!("ordering {equations} equations"),
        Stage::Analyzed {
            factor_len,
            flops,
            seconds,
        } => format!(
            "analysed: {factor_len} entries in L, {:.1} GFlop per factorisation ({seconds:.1} s)",
            flops * 1e-9
        ),
        Stage::Factorization { shift } if *shift == 0.0 => "factorising K".to_string(),
        Stage::Factorization { shift } => {
            format!("factorising K - sigma M, sigma = {shift:.3e}")
        }
        Stage::Factoring { done, flops } => format!(
            "factorising: {:.0} % of {:.1} GFlop",
            100.0 * done,
            flops * 1e-9
        ),
        Stage::Factorized { seconds, .. } => format!("factorised ({seconds:.1} s)"),
        Stage::Iteration {
            step,
            solves,
            converged,
            wanted,
            basis,
        } => format!(
            "Lanczos step {step}: {converged} of {wanted} modes converged \
             ({solves} solves, basis {basis})"
        ),
        Stage::LanczosDone {
            solves,
            block_solves,
            solve_seconds,
            products,
            mass_seconds,
            seconds,
        } => format!(
            "Lanczos done ({seconds:.1} s): {solves} solves in {block_solves} sweeps \
             ({solve_seconds:.1} s), {products} products with M ({mass_seconds:.1} s)"
        ),
        Stage::SturmCheck {
            bound,
            count,
            found,
        } => {
            format!("Sturm check: {count} eigenvalues below {bound:.3e}, {found} found")
        }
        Stage::DenseEigen { equations, wanted } => format!(
            "dense eigen solve of {equations} equations ({wanted} modes, too many for Lanczos)"
        ),
        Stage::Solves { columns: 1 } => "solving for 1 right-hand side".to_string(),
        Stage::Solves { columns } => format!("solving for {columns} right-hand sides"),
        Stage::Done { seconds } => format!("eigenmodes done ({seconds:.1} s)"),
    }
}
