//! The reduction methods of report section 6, each a choice of Ritz basis:
//!
//! | method | report | basis T |
//! | --- | --- | --- |
//! | `free` | 6.3 | free eigenmodes, rigid-body modes included |
//! | `craig-bampton` | 6.4 | constraint modes + fixed-interface eigenmodes |
//! | `elastic-residual` | 6.5 | residual constraint modes + eigenmodes of the elastically supported body |
//! | `free-residual` | 6.6 | rigid-body modes + residual inertia-relief attachment modes + free eigenmodes |
//! | `guyan` | static condensation | constraint modes |
//!
//! Every method reduces the FREE stiffness and mass, `K_red = T^T K T`,
//! `M_red = T^T M T` (eq. 5-7). For `elastic-residual` the springs only shape
//! the basis; they are left to the MBS, which adds `T_j^T c_n K_n T_j`
//! (eq. 26-29), so they are never counted twice.

use crate::body::{ModeKind, ReducedBody};
use crate::modes::eigen::eigenmodes_from;
use crate::modes::elastic_interface::{elastic_residual_modes_from, free_rigid_motions};
use crate::modes::fixed_interface::craig_bampton_modes_from;
use crate::modes::free_interface::inertia_relief_and_free_modes_from;
use crate::modes::zero_modes::{check_zeros, count_zeros, ZERO_GAP};
use crate::modes::{
    self, eigenmodes, rigid_body_modes, statically_determinate_support, unit_loads, RigidModes,
    Wanted,
};
use crate::products::Matrices;
use crate::ReduceError;
use faer::sparse::Triplet;
use faer::Mat;
use flexbody_fem::{Axes, AxesChange, Dof, DofKind, FemError, NodeId, Substructure, Support};
use flexbody_linalg::eigen::leading_zeros;
use flexbody_linalg::memory::Budget;
use flexbody_linalg::progress::{NoProgress, Progress};
use flexbody_linalg::{sparse, LinalgError, SparseMat};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

/// Reduction method (CLI and model-file name in kebab-case).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    Free,
    CraigBampton,
    ElasticResidual,
    FreeResidual,
    Guyan,
}

impl Method {
    pub const ALL: [Method; 5] = [
        Method::Free,
        Method::CraigBampton,
        Method::ElasticResidual,
        Method::FreeResidual,
        Method::Guyan,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::Free => "free",
            Method::CraigBampton => "craig-bampton",
            Method::ElasticResidual => "elastic-residual",
            Method::FreeResidual => "free-residual",
            Method::Guyan => "guyan",
        }
    }

    pub fn parse(s: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == s)
    }

    /// Whether the method's basis takes force groups in place of unit
    /// loads at the interface DOFs: `free` (which ignores them) and
    /// `free-residual` (residual inertia-relief modes per group, report
    /// section 7). The constraint-mode methods (`craig-bampton`, `guyan`,
    /// `elastic-residual`) reduce on the interface DOFs themselves and
    /// refuse force groups ([`ReduceError::ForceGroupsNotApplicable`]).
    pub fn takes_force_groups(self) -> bool {
        match self {
            Method::Free | Method::FreeResidual => true,
            Method::CraigBampton | Method::Guyan | Method::ElasticResidual => false,
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A spring from a node to ground along a direction: the elastic support of
/// report 6.5 (Bild 8). `C_n = c d d^T` on the node's translations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroundSpring {
    pub node: u64,
    /// Unit direction (normalised on use).
    pub direction: [f64; 3],
    /// Stiffness (N/m).
    pub stiffness: f64,
}

/// A force group ("Kraftgruppe", report section 7): a load pattern on
/// interface DOFs used instead of single unit loads, to cut r on bodies with
/// many interface points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ForceGroup {
    pub name: String,
    /// `(DOF, load)` pairs (N or N m per unit of the group's amplitude).
    pub loads: Vec<(Dof, f64)>,
}

/// What to reduce and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Reduction {
    pub method: Method,
    /// Eigenmodes e. For `free` the total r, rigid-body modes included.
    pub modes: usize,
    /// Interface DOFs (H): where the MBS acts on the body.
    pub interface: Vec<Dof>,
    /// Statically determinate support for inertia-relief modes; `None`:
    /// chosen automatically (all DOFs of the first interface node first).
    pub support: Option<Vec<Dof>>,
    /// Elastic supports for `elastic-residual`.
    pub springs: Vec<GroundSpring>,
    /// Rotate the basis so that `M_red = I`, `K_red` diagonal.
    pub orthonormalize: bool,
    /// Load patterns replacing the unit loads of attachment and
    /// inertia-relief modes (empty: unit loads at the interface DOFs).
    pub force_groups: Vec<ForceGroup>,
    /// Keep every eigenmode below this frequency (Hz) instead of `modes`
    /// (the report's e = modes in the excitation band; for `free`, rigid
    /// modes included).
    pub max_frequency_hz: Option<f64>,
    /// The memory the solves may take (the machine's room, and a cap on
    /// this process's resident memory if one is set): a factor, a Lanczos
    /// basis or a dense solve beyond it is refused before it starts.
    pub memory: Budget,
    /// Local axes at nodes (a model's `*TRANSFORM`,
    /// [`flexbody_fem::Model::local_axes`]): the DOFs that `interface`,
    /// `support` and the force groups name at these nodes are along them,
    /// and so are the body's interface rows there
    /// ([`ReducedBody::local_axes`]). The reduction then runs over local
    /// DOFs at those nodes ([`Substructure::in_local_axes`]) and turns the
    /// basis back to global rows; the reduced matrices are the same as for
    /// the model meshed with its local axes along the global ones. Nodes
    /// that none of them names are ignored. Ground springs keep their
    /// global directions.
    pub local_axes: BTreeMap<NodeId, Axes>,
}

impl Reduction {
    pub fn new(method: Method, modes: usize, interface: Vec<Dof>) -> Self {
        Self {
            method,
            modes,
            interface,
            support: None,
            springs: Vec::new(),
            orthonormalize: false,
            force_groups: Vec::new(),
            max_frequency_hz: None,
            memory: Budget::MACHINE,
            local_axes: BTreeMap::new(),
        }
    }
}

/// Reduces the substructure `sub` as `spec` says, unreported. `sub` is
/// left as it was; [`reduce_keeping`] with [`Keep::Both`] gives the same
/// body.
pub fn reduce(sub: &Substructure, spec: &Reduction) -> Result<ReducedBody, ReduceError> {
    reduce_reporting(sub, spec, &NoProgress)
}

/// [`reduce`], the stages of its solves going to `progress`.
pub fn reduce_reporting(
    sub: &Substructure,
    spec: &Reduction,
    progress: &dyn Progress,
) -> Result<ReducedBody, ReduceError> {
    if let Some(local) = Local::of(sub, spec)? {
        let body = reduce_reporting(&local.sub, &local.spec, progress)?;
        return Ok(body_to_global(&local.change, body, &spec.local_axes));
    }
    let checked = check(sub, spec)?;
    let matrices = Matrices::lent(&sub.matrices.stiffness, &sub.matrices.mass).under(spec.memory);
    reduce_from(sub, matrices, checked, spec, progress)
}

/// A reduction over local DOFs ([`Reduction::local_axes`]): the
/// substructure turned at the nodes the spec names, the spec without local
/// axes, and the change of basis back.
struct Local {
    sub: Substructure,
    spec: Reduction,
    change: AxesChange,
}

impl Local {
    /// `None` when no node the spec names has local axes.
    fn of(sub: &Substructure, spec: &Reduction) -> Result<Option<Local>, ReduceError> {
        let mut named: BTreeSet<NodeId> = spec.interface.iter().map(|d| d.node).collect();
        named.extend(spec.support.iter().flatten().map(|d| d.node));
        named.extend(
            spec.force_groups
                .iter()
                .flat_map(|g| g.loads.iter().map(|(d, _)| d.node)),
        );
        let axes: BTreeMap<NodeId, Axes> = spec
            .local_axes
            .iter()
            .filter(|(n, _)| named.contains(n))
            .map(|(n, r)| (*n, *r))
            .collect();
        if axes.is_empty() {
            return Ok(None);
        }
        let (turned, change) = sub.in_local_axes(&axes)?;
        Ok(Some(Local {
            sub: turned,
            spec: Reduction {
                local_axes: BTreeMap::new(),
                ..spec.clone()
            },
            change,
        }))
    }
}

/// The body of a local reduction with its basis over global rows
/// (`Phi = T Phi'`) and the axes of its interface nodes.
fn body_to_global(
    change: &AxesChange,
    mut body: ReducedBody,
    axes: &BTreeMap<NodeId, Axes>,
) -> ReducedBody {
    change.rows_to_global(&mut body.basis);
    let nodes: BTreeSet<NodeId> = body.interface.iter().map(|d| d.node).collect();
    body.local_axes = axes
        .iter()
        .filter(|(n, _)| nodes.contains(n))
        .map(|(n, r)| (*n, *r))
        .collect();
    body
}

/// Which of `sub`'s stiffness and mass a caller of [`reduce_keeping`]
/// needs after the reduction. What it does not need is taken out of `sub`
/// (a 0 x 0 matrix takes its place, also after an error) and dropped as
/// soon as the solver of a large model holds its compact copy, so that the
/// factorisations and the Lanczos run find its memory free. Small models,
/// whose eigen solve is the dense one, hold the matrices to the end.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Keep {
    /// Stiffness and mass stay in `sub` (as [`reduce`] leaves them).
    Both,
    /// Only the mass stays (for the SID's mass invariants); the stiffness
    /// is taken.
    Mass,
    /// Both are taken.
    Neither,
}

/// [`reduce`] on a substructure whose stiffness and mass the caller needs
/// afterwards only as far as `keep` says. The body is [`reduce`]'s bit for
/// bit for every choice: on the sparse paths the products after the modes
/// come from the solver's copy whether the matrices were lent or taken.
/// The stages of the solves go to `progress`.
pub fn reduce_keeping(
    sub: &mut Substructure,
    spec: &Reduction,
    keep: Keep,
    progress: &dyn Progress,
) -> Result<ReducedBody, ReduceError> {
    if keep == Keep::Both {
        return reduce_reporting(sub, spec, progress);
    }
    if let Some(local) = Local::of(sub, spec)? {
        // The turned copy holds the matrices the solves need; the caller's
        // go as `keep` says.
        let Local {
            sub: mut turned,
            spec: local_spec,
            change,
        } = local;
        take(&mut sub.matrices.stiffness)?;
        if keep == Keep::Neither {
            take(&mut sub.matrices.mass)?;
        }
        let body = reduce_keeping(&mut turned, &local_spec, Keep::Neither, progress)?;
        return Ok(body_to_global(&change, body, &spec.local_axes));
    }
    let checked = check(sub, spec);
    let k = take(&mut sub.matrices.stiffness)?;
    let matrices = match keep {
        Keep::Mass => Matrices::stiffness_given(k, &sub.matrices.mass),
        _ => Matrices::given(k, take(&mut sub.matrices.mass)?),
    }
    .under(spec.memory);
    reduce_from(sub, matrices, checked?, spec, progress)
}

/// Takes `a` out, leaving a 0 x 0 matrix.
fn take(a: &mut SparseMat) -> Result<SparseMat, ReduceError> {
    Ok(std::mem::replace(a, sparse::from_triplets(0, 0, &[])?))
}

/// What [`check`] found: the interface equations, the rigid-body modes and
/// the size of the basis besides its eigenmodes.
struct Checked {
    boundary: Vec<usize>,
    rigid: RigidModes,
    /// Basis columns besides the eigenmodes ([`other_columns`]).
    others: usize,
}

/// The checks of `spec` against `sub` before any mode is computed.
fn check(sub: &Substructure, spec: &Reduction) -> Result<Checked, ReduceError> {
    let boundary = interface_equations(sub, &spec.interface)?;
    let needs_interface = spec.method != Method::Free;
    if needs_interface && boundary.is_empty() {
        return Err(ReduceError::NoInterface(spec.method.name()));
    }
    // Every method needs mass (eigenmodes, inertia relief, M_red); without
    // it the first solve would fail with a misleading cause.
    if !sub.matrices.mass.val().iter().any(|&v| v != 0.0) {
        return Err(LinalgError::NoMass.into());
    }
    let rigid = free_body_rigid_modes(sub)?;
    if !spec.force_groups.is_empty() && !spec.method.takes_force_groups() {
        return Err(ReduceError::ForceGroupsNotApplicable(spec.method.name()));
    }
    if spec.max_frequency_hz.is_some() && spec.modes > 0 {
        return Err(ReduceError::ModesAndBand(spec.modes));
    }
    let others = other_columns(spec, boundary.len(), rigid.count());
    if spec.max_frequency_hz.is_none() {
        fits_model(spec, spec.modes, others, sub.dof_map.len())?;
    }
    Ok(Checked {
        boundary,
        rigid,
        others,
    })
}

/// Columns of a method's basis besides its eigenmodes: constraint modes
/// (Craig-Bampton, Guyan, elastic-residual) or rigid-body and residual
/// inertia-relief modes (free-residual), one per interface DOF or force
/// group.
fn other_columns(spec: &Reduction, interface: usize, rigid: usize) -> usize {
    match spec.method {
        Method::Free => 0,
        Method::CraigBampton | Method::Guyan | Method::ElasticResidual => interface,
        Method::FreeResidual if spec.force_groups.is_empty() => rigid + interface,
        Method::FreeResidual => rigid + spec.force_groups.len(),
    }
}

/// A basis of more columns than the model has DOFs is dependent: its
/// `M_red` singular, its residual modes (partly) zero.
fn fits_model(
    spec: &Reduction,
    modes: usize,
    others: usize,
    dofs: usize,
) -> Result<(), ReduceError> {
    if modes + others > dofs {
        return Err(ReduceError::BasisBeyondModel {
            method: spec.method.name(),
            modes,
            others,
            dofs,
        });
    }
    Ok(())
}

/// [`reduce`] on `K` and `M` lent or handed over; `sub` gives the DOFs,
/// the node positions and the damping.
fn reduce_from(
    sub: &Substructure,
    matrices: Matrices<'_>,
    Checked {
        boundary,
        rigid,
        others,
    }: Checked,
    spec: &Reduction,
    progress: &dyn Progress,
) -> Result<ReducedBody, ReduceError> {
    let map = &sub.dof_map;
    // The eigenmodes each method takes: a count, or the band below fmax
    // (found in one solve on the problem the method uses).
    let band = |extra: usize| match spec.max_frequency_hz {
        None => Wanted::Lowest(spec.modes + extra),
        Some(f) => Wanted::below_hz(f),
    };
    let (basis, kinds, products) = match spec.method {
        Method::Free => {
            if band(0).is_none() {
                return Err(ReduceError::NoModes);
            }
            // One eigenmode beyond the rigid-body modes at least: a
            // mechanism's zero would be the next (eq. 12-13 give nr).
            let (nr, n) = (rigid.count(), sub.len());
            let wanted = band(0).map_count(|count| count.max(nr + 1).min(n));
            let (mut phi, _, products) = eigenmodes_from(matrices, wanted, progress)?;
            if phi.values.is_empty() {
                return Err(ReduceError::NoModes);
            }
            check_zeros(&phi.values, nr, n, |c| products.lowest_eigenvalues(c))?;
            if phi.values.len() <= nr && phi.values.len() < n {
                // A band of rigid-body modes alone: the next one tells.
                let next = products.lowest_eigenvalues(nr + 1)?;
                check_zeros(&next, nr, n, |c| products.lowest_eigenvalues(c))?;
            }
            if let Some(count) = band(0).count() {
                phi = phi.slice(0, count.min(phi.values.len()));
            }
            let kinds = phi
                .frequencies_hz()
                .into_iter()
                .map(|f| ModeKind::Eigen { frequency_hz: f })
                .collect();
            (phi.vectors, kinds, products)
        }
        Method::CraigBampton | Method::Guyan => {
            if spec.method == Method::Guyan && spec.modes > 0 {
                return Err(ReduceError::GuyanWithModes(spec.modes));
            }
            let band = match spec.method {
                Method::Guyan => Wanted::Lowest(0),
                _ => band(0),
            };
            let (psi, phi, products) =
                craig_bampton_modes_from(matrices, &boundary, map, &rigid, band, progress)?;
            let mut kinds: Vec<ModeKind> = boundary
                .iter()
                .map(|&i| ModeKind::Constraint { dof: map.dof(i) })
                .collect();
            kinds.extend(eigen_kinds(&phi));
            (concat(&[&psi, &phi.vectors]), kinds, products)
        }
        Method::ElasticResidual => {
            let springs = support_stiffness(sub, &spec.springs)?;
            // Rigid-body motions the springs leave free are zero-frequency
            // eigenmodes of K + C, which the constraint modes span already
            // (eq. 14-17): in the basis they would make it dependent. They
            // stay out, and e counts the eigenmodes beyond them, as for
            // free-residual.
            let free = free_rigid_motions(&springs, &rigid)?;
            let (psi, all, products) = elastic_residual_modes_from(
                matrices,
                springs,
                &boundary,
                map,
                &rigid,
                band(free),
                progress,
            )?;
            if free > 0 {
                check_zeros(&all.values, free, sub.len(), |c| {
                    products.lowest_eigenvalues(c)
                })?;
            }
            let phi = all.slice(free.min(all.values.len()), all.values.len());
            let res = products.residual_modes(&psi, &phi.vectors);
            let mut kinds: Vec<ModeKind> = boundary
                .iter()
                .map(|&i| ModeKind::ResidualConstraint { dof: map.dof(i) })
                .collect();
            kinds.extend(eigen_kinds(&phi));
            (concat(&[&res, &phi.vectors]), kinds, products)
        }
        Method::FreeResidual => {
            let nr = rigid.count();
            let support = match &spec.support {
                Some(dofs) => interface_equations(sub, dofs)?,
                None => {
                    let first = map.dof(boundary[0]).node;
                    let preferred: Vec<usize> =
                        map.node_dofs(first).into_iter().map(|(_, i)| i).collect();
                    statically_determinate_support(&rigid, &preferred)
                }
            };
            let loads = if spec.force_groups.is_empty() {
                unit_loads(map.len(), &boundary)
            } else {
                group_loads(sub, &spec.force_groups)?
            };
            let (t_a, all, products) = inertia_relief_and_free_modes_from(
                matrices,
                &rigid,
                &loads,
                &support,
                map,
                band(nr),
                progress,
            )?;
            check_zeros(&all.values, nr, sub.len(), |c| {
                products.lowest_eigenvalues(c)
            })?;
            let e = match band(nr) {
                Wanted::Lowest(_) => spec.modes,
                Wanted::Below(_) | Wanted::LowestBelow { .. } => {
                    all.values.len().saturating_sub(nr)
                }
            };
            if all.values.len() < nr + e {
                return Err(ReduceError::NotEnoughModes {
                    requested: e,
                    available: all.values.len().saturating_sub(nr),
                });
            }
            let mut phi = all.slice(nr, nr + e);
            // Exact M-orthogonality to the geometric rigid-body modes.
            phi.vectors = products.residual_modes(&phi.vectors, &rigid.vectors);
            let res = products.residual_modes(&t_a, &phi.vectors);
            let mut kinds: Vec<ModeKind> = rigid
                .motions
                .iter()
                .map(|k| ModeKind::Rigid { motion: k.clone() })
                .collect();
            if spec.force_groups.is_empty() {
                kinds.extend(
                    boundary
                        .iter()
                        .map(|&i| ModeKind::ResidualInertiaRelief { dof: map.dof(i) }),
                );
            } else {
                kinds.extend(
                    spec.force_groups
                        .iter()
                        .map(|g| ModeKind::ResidualForceGroup {
                            name: g.name.clone(),
                        }),
                );
            }
            kinds.extend(eigen_kinds(&phi));
            (
                concat(&[&rigid.vectors, &res, &phi.vectors]),
                kinds,
                products,
            )
        }
    };
    // A band's modes are known only now.
    fits_model(
        spec,
        basis.ncols().saturating_sub(others),
        others,
        map.len(),
    )?;
    let body = ReducedBody {
        method: spec.method,
        dof_map: map.clone(),
        mass: products.project_mass(basis.as_ref()),
        stiffness: products.project_stiffness(basis.as_ref()),
        damping: sub
            .matrices
            .damping
            .as_ref()
            .map(|d| sparse::project(d, basis.as_ref())),
        basis,
        modes: kinds,
        interface: spec.interface.clone(),
        local_axes: Default::default(),
    };
    if spec.orthonormalize {
        Ok(body.orthonormalized()?)
    } else {
        Ok(body)
    }
}

/// The load matrix of force groups (m x groups).
fn group_loads(sub: &Substructure, groups: &[ForceGroup]) -> Result<Mat<f64>, ReduceError> {
    let mut p = Mat::zeros(sub.len(), groups.len());
    for (j, g) in groups.iter().enumerate() {
        if g.loads.is_empty() {
            return Err(ReduceError::ForceGroup {
                name: g.name.clone(),
                reason: "it has no loads".into(),
            });
        }
        for (dof, value) in &g.loads {
            let i = sub
                .dof_map
                .index_of(*dof)
                .ok_or_else(|| ReduceError::ForceGroup {
                    name: g.name.clone(),
                    reason: format!("{dof} is not a free DOF of the model"),
                })?;
            if !value.is_finite() {
                return Err(ReduceError::ForceGroup {
                    name: g.name.clone(),
                    reason: format!("load {value} at {dof} is not finite"),
                });
            }
            p[(i, j)] += value;
        }
    }
    Ok(p)
}

/// Equation numbers of `dofs`, checked: known, free, not repeated.
pub fn interface_equations(sub: &Substructure, dofs: &[Dof]) -> Result<Vec<usize>, ReduceError> {
    let mut eq = Vec::with_capacity(dofs.len());
    for d in dofs {
        let i = sub
            .dof_map
            .index_of(*d)
            .ok_or(ReduceError::UnknownInterfaceDof(*d))?;
        if eq.contains(&i) {
            return Err(ReduceError::DuplicateInterfaceDof(*d));
        }
        eq.push(i);
    }
    Ok(eq)
}

/// Rigid-body modes of a free substructure: from geometry about the node
/// centroid (eq. 12-13) when node positions are known, else the
/// zero-frequency eigenmodes of K and M (matrices only); none for a
/// supported substructure (fixed DOFs or springs to ground).
pub fn free_body_rigid_modes(sub: &Substructure) -> Result<RigidModes, ReduceError> {
    let none = || RigidModes {
        vectors: Mat::zeros(sub.len(), 0),
        motions: vec![],
    };
    match sub.support {
        Support::Supported => return Ok(none()),
        Support::Unknown if !sub.has_geometry() => return null_space_modes(sub),
        Support::Unknown => {
            // Geometry known but support unknown: a regular K has no rigid modes.
            let modes = null_space_modes(sub)?;
            if modes.count() == 0 {
                return Ok(modes);
            }
        }
        Support::Free => {}
    }
    let matrices = &sub.matrices;
    let rigid = rigid_body_modes(sub, sub.centroid());
    let ratio = modes::rigid::strain_energy_ratio(&matrices.stiffness, &rigid);
    if ratio > 1e-8 {
        return Err(ReduceError::RigidModesStrained(ratio));
    }
    Ok(rigid)
}

/// Rigid-body modes as the zero-frequency eigenmodes of K and M: those
/// below a gap of [`ZERO_GAP`] to the next eigenvalue, at most six.
fn null_space_modes(sub: &Substructure) -> Result<RigidModes, ReduceError> {
    let n = sub.len();
    let pairs = eigenmodes(
        &sub.matrices.stiffness,
        &sub.matrices.mass,
        Wanted::Lowest(n.min(7)),
    )?;
    let v = &pairs.values;
    let top = v.last().copied().unwrap_or(0.0);
    let count = leading_zeros(v, top, ZERO_GAP);
    if count == 7 {
        let (k, m) = (&sub.matrices.stiffness, &sub.matrices.mass);
        let zero = count_zeros(v.clone(), n, |c| {
            Ok(eigenmodes(k, m, Wanted::Lowest(c))?.values)
        })?;
        return Err(ReduceError::FreeMechanism { zero, rigid: 6 });
    }
    Ok(RigidModes {
        vectors: pairs.vectors.subcols(0, count).to_owned(),
        motions: (1..=count)
            .map(|k| format!("zero-energy mode {k}"))
            .collect(),
    })
}

/// Sparse `sum_n c_n d_n d_n^T` on the translations of each spring's node.
pub fn support_stiffness(
    sub: &Substructure,
    springs: &[GroundSpring],
) -> Result<SparseMat, ReduceError> {
    let map = &sub.dof_map;
    let mut t = Vec::new();
    for s in springs {
        flexbody_fem::require_positive(
            format!("stiffness of the spring at node {}", s.node),
            s.stiffness,
        )?;
        let d = unit(s.direction).ok_or_else(|| {
            ReduceError::Fem(FemError::InvalidValue {
                what: format!("direction of the spring at node {}", s.node),
                rule: "non-zero",
                value: 0.0,
            })
        })?;
        // Along the node's local axes where its equations are (d' = R^T d).
        let d = match sub.local_axes.get(&s.node) {
            Some(r) => std::array::from_fn(|i| (0..3).map(|j| r[j][i] * d[j]).sum()),
            None => d,
        };
        let kinds = [DofKind::Ux, DofKind::Uy, DofKind::Uz];
        let mut eq = [None; 3];
        for a in 0..3 {
            if d[a] != 0.0 {
                eq[a] = Some(sub.equation(Dof::new(s.node, kinds[a]), "support spring")?);
            }
        }
        for a in 0..3 {
            for b in 0..3 {
                if let (Some(i), Some(j)) = (eq[a], eq[b]) {
                    t.push(Triplet::new(i, j, s.stiffness * d[a] * d[b]));
                }
            }
        }
    }
    Ok(sparse::from_triplets(map.len(), map.len(), &t)?)
}

/// `v / |v|`, or `None` for a zero vector.
pub fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

fn eigen_kinds(phi: &modes::EigenModes) -> Vec<ModeKind> {
    phi.frequencies_hz()
        .into_iter()
        .map(|f| ModeKind::Eigen { frequency_hz: f })
        .collect()
}

/// Side-by-side concatenation of column blocks with equal row counts.
fn concat(blocks: &[&Mat<f64>]) -> Mat<f64> {
    let n = blocks.first().map_or(0, |b| b.nrows());
    let cols: usize = blocks.iter().map(|b| b.ncols()).sum();
    let mut out = Mat::zeros(n, cols);
    let mut c0 = 0;
    for b in blocks {
        out.subcols_mut(c0, b.ncols()).copy_from(b.as_ref());
        c0 += b.ncols();
    }
    out
}
