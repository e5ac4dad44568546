//! Linear-algebra kernels of flexbody, over faer's matrix types.
//!
//! Other crates keep their data in faer's [`faer::Mat`] and
//! [`faer::sparse::SparseColMat`] and call these algorithms:
//! - [`ldlt`]: sparse `LDL^T` by phases: the symbolic analysis (supernodes
//!   found on the node graph, and the plans of the parallel steps), the
//!   numeric factorisation, block solves, pivot inspection (singularity,
//!   inertia);
//! - [`solver`]: the one eigen entry point, choosing the dense or the
//!   sparse solver by size and request;
//! - [`eigen`]: the generalized symmetric eigenproblem `K x = lambda M x`,
//!   dense;
//! - [`lanczos`]: its sparse solver for large models (shift-invert block
//!   Lanczos, thick restart, Sturm check), over [`pencil`] and the
//!   fill-reducing [`ordering`], reporting to a [`progress`] hook;
//! - [`orthonormal`]: M-orthonormalisation of a basis with rank detection;
//! - [`sparse`]: assembly from triplets, sub-matrices, products.

pub mod dense_check;
pub mod eigen;
pub mod lanczos;
pub mod ldlt;
mod lower;
pub mod memory;
pub mod ordering;
pub mod orthonormal;
pub mod pencil;
pub mod progress;
pub mod solver;
pub mod sparse;
mod tall;

pub use faer::sparse::SparseColMat;
pub use faer::{Mat, MatRef};

/// Sparse matrix type used throughout flexbody (column-compressed, `usize` indices).
pub type SparseMat = SparseColMat<usize, f64>;

/// Errors of the linear-algebra kernels. Indices are rows of the matrix that
/// was handed in (original order, not the fill-reducing permutation).
#[derive(Debug, thiserror::Error)]
pub enum LinalgError {
    /// A pivot of `LDL^T` vanished: the matrix is singular at this row.
    #[error("matrix is singular: pivot {pivot:e} at row {index} (diagonal {diagonal:e})")]
    Singular {
        index: usize,
        pivot: f64,
        diagonal: f64,
    },
    /// Eigenvalues lie below a bound that none may cross: below a shift
    /// under the rigid-body modes' zeros, or clearly negative.
    #[error("{count} eigenvalue(s) of K phi = lambda M phi lie below {bound:e} (1/s^2), where none may: K is not positive semi-definite (a structure unstable under its preload, a negative stiffness) or M is not positive")]
    NotSemiDefinite { count: usize, bound: f64 },
    /// The dense eigen solver was asked for a pencil beyond its limit.
    #[error(
        "{dofs} DOFs is beyond the dense eigen solver (limit {limit}); use the sparse solver (Solver::Sparse or Auto)"
    )]
    TooLargeForDense { dofs: usize, limit: usize },
    /// The mass matrix is zero: an eigen solve needs mass.
    #[error("the mass matrix is zero: natural frequencies need mass (is every density 0?)")]
    NoMass,
    /// Dimensions of the operands do not agree.
    #[error("dimension mismatch: {0}")]
    Dimension(String),
    /// An eigen request the solvers cannot serve on this pencil: more
    /// pairs than it has, or than the Lanczos basis and the dense solver
    /// can hold, or a free body's request without an elastic mode.
    #[error("eigen request not served: {0}")]
    Unservable(String),
    /// A factor (or other large array) would not fit in the memory left.
    #[error("{what} needs {needed} more memory, but only {room} are left ({bound}): use a machine with more memory or a coarser mesh")]
    OutOfMemory {
        what: String,
        needed: String,
        room: String,
        bound: String,
    },
    /// The mass matrix of a set of Ritz vectors is singular.
    #[error("the mass matrix resolves {modes} modes for {coordinates} coordinates: the others combine to a mass at round-off (nearly dependent Ritz vectors, such as residual modes of interface nodes close together)")]
    MasslessDirections { modes: usize, coordinates: usize },
    /// The Lanczos runs found fewer eigenvalues below a bound than the
    /// Sturm count says there are, after the runs allowed.
    #[error("linear algebra failure: the Lanczos runs found {found} of the {count} eigenvalues below {bound:.6e} (Sturm count) in {runs} runs after the first")]
    SturmMissing {
        found: usize,
        count: usize,
        bound: f64,
        runs: usize,
    },
    /// The Lanczos runs found more eigenvalues below a bound than the Sturm
    /// count has: pairs found twice or spurious ones.
    #[error("linear algebra failure: the Lanczos runs found {found} eigenvalues below {bound:.6e} where the Sturm count has {count}: spurious eigenpairs")]
    SturmSpurious {
        found: usize,
        count: usize,
        bound: f64,
    },
    /// `K - s M` stayed singular at every shift tried near a bound.
    #[error("linear algebra failure: no Sturm count near {bound:e}: K - s M stays singular")]
    NoSturmCount { bound: f64 },
    /// The Lanczos iterations did not converge in the steps allowed.
    #[error("linear algebra failure: Lanczos did not converge in {steps} steps ({wanted} eigenpairs wanted)")]
    NotConverged { steps: usize, wanted: usize },
    /// A dense matrix handed in has a non-finite entry.
    #[error("linear algebra failure: symmetric eigen-decomposition of a {n}x{n} matrix with a non-finite entry")]
    NonFinite { n: usize },
    /// The fill-reducing ordering failed (a graph too large for METIS's
    /// 32-bit indices, or METIS's own error).
    #[error("linear algebra failure: {0}")]
    Ordering(String),
    /// faer could not complete an operation (out of memory, index overflow).
    #[error("linear algebra failure: {0}")]
    Faer(String),
}
