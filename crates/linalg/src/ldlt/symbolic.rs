//! The symbolic phase of a sparse `LDL^T`: the supernodal structure of the
//! factor, its analysis on the node graph, and the plans of the parallel
//! numeric steps, made once per analysis: [`SolvePlan`] (disjoint subtrees
//! of the elimination tree and the supernodes above them) and
//! [`UpdatePlan`] (which descendants update which supernode).
//!
//! A supernode is a range of consecutive columns of `L` whose rows below
//! their diagonal block share one pattern. Its values are one column-major
//! block: the diagonal block's rows first, then the pattern's (faer's
//! layout, which the numeric factorisation and [`crate::ldlt::solve`] read).
//!
//! The 3 translations of a solid node have the same closed neighbourhood
//! (adjacency plus themselves), and nested dissection keeps them together
//! ([`crate::ordering`]). Such equations always fall into one supernode, so
//! the elimination tree, the column counts, the supernodes and their
//! patterns can be computed on the graph of these *groups* and expanded to
//! the equations afterwards: `Supernodes::of_dissection` does faer's
//! symbolic analysis (fundamental supernodes, then its relaxed
//! amalgamation) on a graph 3 times smaller with 9 times fewer edges, and
//! gives faer's structure exactly, entry for entry.

use crate::ordering::{mix, neighbourhoods, Dissection, NodeGraph};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::SymbolicSparseColMatRef;
use faer::MatRef;
use std::ops::Range;

/// faer's amalgamation: a child supernode merges into its parent while the
/// merged size is at most `.0` columns and at most the fraction `.1` of the
/// merged block's entries are structural zeros.
const RELAX: [(usize, f64); 4] = [(4, 1.0), (16, 0.8), (48, 0.1), (usize::MAX, 0.05)];

/// faer's choice of a supernodal over a simplicial factor: flops per entry
/// of `L` above this.
const SUPERNODAL_FLOPS_PER_ENTRY: f64 = 40.0;

/// The supernodes of a factor `L` of dimension `nrows()`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Supernodes {
    dim: usize,
    /// `begin[s]..begin[s + 1]`: the columns of supernode `s`.
    begin: Vec<usize>,
    /// `rows[row_ptr[s]..row_ptr[s + 1]]`: the pattern of `s`, ascending.
    row_ptr: Vec<usize>,
    /// `val_ptr[s]..val_ptr[s + 1]`: the values of `s`'s block.
    val_ptr: Vec<usize>,
    rows: Vec<usize>,
}

/// Where supernode `s` sits: its first column and its pattern.
#[derive(Copy, Clone, Debug)]
pub(crate) struct SupernodeRef<'a> {
    start: usize,
    pattern: &'a [usize],
}

impl<'a> SupernodeRef<'a> {
    /// The rows below the diagonal block, ascending.
    pub(crate) fn pattern(self) -> &'a [usize] {
        self.pattern
    }
}

/// A supernode's place and values.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Block<'a> {
    node: SupernodeRef<'a>,
    val: MatRef<'a, f64>,
}

impl<'a> Block<'a> {
    pub(crate) fn start(self) -> usize {
        self.node.start
    }

    pub(crate) fn pattern(self) -> &'a [usize] {
        self.node.pattern
    }

    /// The diagonal block's rows, then the pattern's; one column each.
    pub(crate) fn val(self) -> MatRef<'a, f64> {
        self.val
    }
}

/// A factor: its supernodes and their values.
#[derive(Copy, Clone, Debug)]
pub(crate) struct FactorRef<'a> {
    symbolic: &'a Supernodes,
    values: &'a [f64],
}

impl<'a> FactorRef<'a> {
    pub(crate) fn new(symbolic: &'a Supernodes, values: &'a [f64]) -> Self {
        assert_eq!(values.len(), symbolic.len_val());
        Self { symbolic, values }
    }

    pub(crate) fn supernode(self, s: usize) -> Block<'a> {
        let node = self.symbolic.supernode(s);
        let ncols = self.symbolic.begin[s + 1] - self.symbolic.begin[s];
        let ptr = &self.symbolic.val_ptr;
        let val = MatRef::from_column_major_slice(
            &self.values[ptr[s]..ptr[s + 1]],
            ncols + node.pattern.len(),
            ncols,
        );
        Block { node, val }
    }
}

impl Supernodes {
    /// faer's supernodal structure, copied.
    pub(crate) fn from_faer(s: &SymbolicSupernodalCholesky<usize>) -> Self {
        let ns = s.n_supernodes();
        let mut begin = s.supernode_begin().to_vec();
        begin.push(s.supernode_end().last().copied().unwrap_or(0));
        let mut row_ptr = Vec::with_capacity(ns + 1);
        let mut rows = Vec::new();
        row_ptr.push(0);
        for k in 0..ns {
            rows.extend_from_slice(s.supernode(k).pattern());
            row_ptr.push(rows.len());
        }
        Self {
            dim: s.nrows(),
            begin,
            row_ptr,
            val_ptr: s.col_ptr_for_val().to_vec(),
            rows,
        }
    }

    pub fn n_supernodes(&self) -> usize {
        self.begin.len() - 1
    }

    pub fn nrows(&self) -> usize {
        self.dim
    }

    /// Length of the factor's values.
    pub fn len_val(&self) -> usize {
        self.val_ptr[self.n_supernodes()]
    }

    /// First column of each supernode.
    pub fn supernode_begin(&self) -> &[usize] {
        &self.begin[..self.n_supernodes()]
    }

    /// One past the last column of each supernode.
    pub fn supernode_end(&self) -> &[usize] {
        &self.begin[1..]
    }

    /// `col_ptr_for_val()[s]..[s + 1]`: the values of supernode `s`.
    pub fn col_ptr_for_val(&self) -> &[usize] {
        &self.val_ptr
    }

    /// Floating-point operations of the numeric factorisation, `sum_j c_j^2`
    /// over the columns `j` of `L` with `c_j` entries below the diagonal
    /// (one multiply and one add per entry of each column's outer-product
    /// update).
    pub fn flops(&self) -> f64 {
        (0..self.n_supernodes())
            .map(|s| {
                supernode_flops(
                    self.begin[s + 1] - self.begin[s],
                    self.row_ptr[s + 1] - self.row_ptr[s],
                )
            })
            .sum()
    }

    pub(crate) fn supernode(&self, s: usize) -> SupernodeRef<'_> {
        SupernodeRef {
            start: self.begin[s],
            pattern: &self.rows[self.row_ptr[s]..self.row_ptr[s + 1]],
        }
    }

    /// The supernodal analysis of the symmetric `pattern` (its lower
    /// triangle is read) in the order `dissection`, computed on the groups
    /// of consecutive equations (in that order) with equal closed
    /// neighbourhoods and expanded to the equations. `None` where faer
    /// would choose a simplicial factor (few flops per entry of `L`).
    ///
    /// The groups and their graph are METIS's vertices and edges where the
    /// order came from [`crate::ordering::nested_dissection`] of this
    /// pattern (or of one that contains it); otherwise they are recognised
    /// here by a 64-bit hash of each equation's neighbourhood. A collision
    /// would join equations that differ; a group is treated as coupled in
    /// full, so the pattern would hold explicit zeros, never miss an entry.
    pub(crate) fn of_dissection(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        dissection: &Dissection,
    ) -> Option<Self> {
        let n = pattern.nrows();
        if n == 0 {
            return None;
        }
        let (forward, inverse) = (&dissection.forward, &dissection.inverse);
        let of_vertices = dissection
            .graph
            .as_ref()
            .and_then(|g| Groups::of_vertices(forward, g));
        let (groups, graph) = match of_vertices {
            Some(both) => both,
            None => {
                let (groups, of_old) = Groups::hashed(pattern, forward, inverse);
                let graph = groups.upper_graph(pattern, &of_old);
                (groups, graph)
            }
        };
        Self::of_groups(n, &groups, &graph)
    }

    /// The analysis on `groups` of the `n` equations, coupled as `graph`.
    fn of_groups(n: usize, groups: &Groups, graph: &Graph) -> Option<Self> {
        let ng = groups.len();
        let weight = |g: usize| groups.start[g + 1] - groups.start[g];
        let parent = elimination_tree(graph);
        // Row subtrees: row K of L holds the columns on the paths from
        // each neighbour I < K up to K. `degree[J]`: equations below J's
        // own in its column.
        let mut degree = vec![0usize; ng];
        let mut mark = vec![usize::MAX; ng];
        for k in 0..ng {
            mark[k] = k;
            for &i in graph.of(k) {
                let mut j = i as usize;
                while mark[j] != k {
                    mark[j] = k;
                    degree[j] += weight(k);
                    j = parent[j];
                }
            }
        }
        drop(mark);
        if !supernodal_pays(weight, &degree) {
            return None;
        }
        // Fundamental supernodes: a group joins its predecessor's when it
        // is that one's parent, its only child, and its column is the
        // predecessor's without the diagonal.
        let mut children = vec![0usize; ng];
        for &p in &parent[..ng] {
            if p != NONE {
                children[p] += 1;
            }
        }
        let mut fund_start = vec![0usize];
        for j in 1..ng {
            let joins =
                parent[j - 1] == j && children[j] == 1 && degree[j - 1] == weight(j) + degree[j];
            if !joins {
                fund_start.push(j);
            }
        }
        fund_start.push(ng);
        let nf = fund_start.len() - 1;
        let (_, fund_parent) = supernode_tree(&fund_start, &parent);
        let fund_size: Vec<usize> = (0..nf)
            .map(|f| groups.start[fund_start[f + 1]] - groups.start[fund_start[f]])
            .collect();
        let fund_degree: Vec<usize> = (0..nf).map(|f| degree[fund_start[f + 1] - 1]).collect();
        // Relaxed supernodes: runs of fundamental ones, each merged into
        // the next.
        let kept = relax(&fund_parent, &fund_size, &fund_degree);
        let mut super_start = vec![0usize];
        for f in 0..nf {
            if kept[f] {
                super_start.push(fund_start[f + 1]);
            }
        }
        let ns = super_start.len() - 1;
        let (group_super, super_parent) = supernode_tree(&super_start, &parent);
        // Patterns (in groups): row K joins every supernode on the paths
        // from its neighbours' supernodes up to its own.
        let mut visited = vec![usize::MAX; ns];
        let mut walk = |f: &mut dyn FnMut(usize, usize)| {
            visited.fill(usize::MAX);
            for k in 0..ng {
                visited[group_super[k]] = k;
                for &i in graph.of(k) {
                    let mut s = group_super[i as usize];
                    while visited[s] != k {
                        visited[s] = k;
                        f(s, k);
                        s = super_parent[s];
                    }
                }
            }
        };
        let mut count = vec![0usize; ns + 1];
        walk(&mut |s, _| count[s + 1] += 1);
        for s in 0..ns {
            count[s + 1] += count[s];
        }
        let mut next = count.clone();
        let mut group_rows = vec![0u32; count[ns]];
        walk(&mut |s, k| {
            group_rows[next[s]] = k as u32;
            next[s] += 1;
        });
        // Expanded to the equations, the rows written by both threads.
        let start = &groups.start;
        let begin: Vec<usize> = super_start.iter().map(|&g| start[g]).collect();
        let mut row_ptr = Vec::with_capacity(ns + 1);
        let mut val_ptr = Vec::with_capacity(ns + 1);
        row_ptr.push(0);
        val_ptr.push(0);
        for s in 0..ns {
            let len: usize = group_rows[count[s]..count[s + 1]]
                .iter()
                .map(|&k| weight(k as usize))
                .sum();
            row_ptr.push(row_ptr[s] + len);
            let ncols = begin[s + 1] - begin[s];
            val_ptr.push(val_ptr[s] + (ncols + len) * ncols);
        }
        let mut rows = vec![0usize; row_ptr[ns]];
        let expansion = Expansion {
            row_ptr: &row_ptr,
            group_ptr: &count,
            group_rows: &group_rows,
            start,
        };
        expansion.write(&mut rows, 0..ns);
        Some(Self {
            dim: n,
            begin,
            row_ptr,
            val_ptr,
            rows,
        })
    }
}

/// The patterns of supernodes in groups, written out in equations.
struct Expansion<'a> {
    row_ptr: &'a [usize],
    group_ptr: &'a [usize],
    group_rows: &'a [u32],
    start: &'a [usize],
}

impl Expansion<'_> {
    /// The rows of `supernodes` into `rows`, halves in parallel.
    fn write(&self, rows: &mut [usize], supernodes: std::ops::Range<usize>) {
        let first = self.row_ptr[supernodes.start];
        if rows.len() > 1 << 16 && supernodes.len() > 1 {
            let half = first + rows.len() / 2;
            let mid = self.row_ptr[supernodes.clone()]
                .partition_point(|&p| p < half)
                .clamp(1, supernodes.len() - 1)
                + supernodes.start;
            let (left, right) = rows.split_at_mut(self.row_ptr[mid] - first);
            rayon::join(
                || self.write(left, supernodes.start..mid),
                || self.write(right, mid..supernodes.end),
            );
            return;
        }
        let mut out = rows.iter_mut();
        let groups =
            &self.group_rows[self.group_ptr[supernodes.start]..self.group_ptr[supernodes.end]];
        for &k in groups {
            for r in self.start[k as usize]..self.start[k as usize + 1] {
                if let Some(slot) = out.next() {
                    *slot = r;
                }
            }
        }
    }
}

const NONE: usize = usize::MAX;

/// Runs of consecutive equations (in the new order) with equal closed
/// neighbourhoods.
struct Groups {
    /// `start[g]..start[g + 1]`: the new positions of group `g`.
    start: Vec<usize>,
}

impl Groups {
    /// The groups on METIS's graph, and their graph: runs of the order
    /// over vertices with equal closed neighbourhoods (by a hash). METIS's
    /// vertices join equations consecutive in the original order; here
    /// also vertices that the order put side by side (a node on each face
    /// of a wall one element thick: 54300 groups of 99912 vertices at 3e5
    /// DOFs of the C3D8 beam). `None` if a vertex is not one run of the
    /// order.
    fn of_vertices(forward: &[usize], g: &NodeGraph) -> Option<(Self, Graph)> {
        let n = forward.len();
        let nv = g.xadj.len() - 1;
        let neighbours = |v: usize| &g.adjncy[g.xadj[v] as usize..g.xadj[v + 1] as usize];
        let hash: Vec<u64> = (0..nv)
            .map(|v| {
                neighbours(v)
                    .iter()
                    .fold(mix(v), |h, &w| h.wrapping_add(mix(w as usize)))
            })
            .collect();
        let same =
            |v: usize, w: usize| hash[v] == hash[w] && neighbours(v).len() == neighbours(w).len();
        let vertex = |p: usize| g.vertex_of[forward[p]] as usize;
        let mut start = Vec::new();
        let mut group_of = vec![u32::MAX; nv];
        for p in 0..n {
            let v = vertex(p);
            if p > 0 && v == vertex(p - 1) {
                continue;
            }
            if group_of[v] != u32::MAX {
                return None;
            }
            if p == 0 || !same(v, vertex(p - 1)) {
                start.push(p);
            }
            group_of[v] = (start.len() - 1) as u32;
        }
        start.push(n);
        let ng = start.len() - 1;
        // A group's neighbours: those of all its vertices (the same ones,
        // but where a hash collided).
        let mut ptr = Vec::with_capacity(ng + 1);
        let mut adj = Vec::new();
        let mut mark = vec![u32::MAX; ng];
        ptr.push(0);
        for k in 0..ng {
            mark[k] = k as u32;
            let mut last = usize::MAX;
            for p in start[k]..start[k + 1] {
                let v = vertex(p);
                if v == last {
                    continue;
                }
                last = v;
                for &w in neighbours(v) {
                    let i = group_of[w as usize];
                    if i < k as u32 && mark[i as usize] != k as u32 {
                        mark[i as usize] = k as u32;
                        adj.push(i);
                    }
                }
            }
            ptr.push(adj.len());
        }
        Some((Self { start }, Graph { ptr, adj }))
    }

    /// The groups by a hash of each equation's closed neighbourhood, and
    /// the group of each equation in the original order.
    fn hashed(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        forward: &[usize],
        inverse: &[usize],
    ) -> (Self, Vec<u32>) {
        let n = pattern.nrows();
        let key = neighbourhoods(pattern);
        let mut start = vec![0usize];
        let mut of_new = vec![0u32; n];
        for p in 1..n {
            if key[forward[p - 1]] != key[forward[p]] {
                start.push(p);
            }
            of_new[p] = (start.len() - 1) as u32;
        }
        start.push(n);
        let of_old = inverse.iter().map(|&p| of_new[p]).collect();
        (Self { start }, of_old)
    }

    fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// For each group `K`, the groups `I < K` coupled with it in `pattern`
    /// (`of[old]`: the group of each equation).
    fn upper_graph(&self, pattern: SymbolicSparseColMatRef<'_, usize>, of: &[u32]) -> Graph {
        let ng = self.len();
        let n = pattern.nrows();
        // Both passes skip a row of the same group as the one before it
        // (a neighbour's equations are adjacent rows).
        let pairs = |f: &mut dyn FnMut(u32, u32)| {
            for j in 0..n {
                let gj = of[j];
                let mut last = gj;
                for i in pattern.row_idx_of_col(j).filter(|&i| i > j) {
                    let gi = of[i];
                    if gi != last {
                        last = gi;
                        if gi != gj {
                            f(gi.max(gj), gi.min(gj));
                        }
                    }
                }
            }
        };
        let mut ptr = vec![0usize; ng + 1];
        pairs(&mut |k, _| ptr[k as usize + 1] += 1);
        for k in 0..ng {
            ptr[k + 1] += ptr[k];
        }
        let mut next = ptr.clone();
        let mut adj = vec![0u32; ptr[ng]];
        pairs(&mut |k, i| {
            adj[next[k as usize]] = i;
            next[k as usize] += 1;
        });
        // Duplicates out, in place.
        let mut mark = vec![u32::MAX; ng];
        let mut out = 0;
        let mut compact = vec![0usize; ng + 1];
        for k in 0..ng {
            for p in ptr[k]..ptr[k + 1] {
                let i = adj[p];
                if mark[i as usize] != k as u32 {
                    mark[i as usize] = k as u32;
                    adj[out] = i;
                    out += 1;
                }
            }
            compact[k + 1] = out;
        }
        adj.truncate(out);
        Graph { ptr: compact, adj }
    }
}

/// Adjacency lists by group.
struct Graph {
    ptr: Vec<usize>,
    adj: Vec<u32>,
}

impl Graph {
    fn of(&self, k: usize) -> &[u32] {
        &self.adj[self.ptr[k]..self.ptr[k + 1]]
    }
}

/// [`Supernodes::flops`] of one supernode of `width` columns and `pattern`
/// rows below its diagonal block.
pub(crate) fn supernode_flops(width: usize, pattern: usize) -> f64 {
    (0..width)
        .map(|k| ((width - 1 - k + pattern) as f64).powi(2))
        .sum()
}

/// The supernodes of the ranges of groups `start[s]..start[s + 1]`: the
/// supernode of each group, and the parent of each supernode in the
/// groups' elimination tree `parent` (`NONE` for a root).
fn supernode_tree(start: &[usize], parent: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let ns = start.len() - 1;
    let mut of = vec![0usize; parent.len()];
    for s in 0..ns {
        of[start[s]..start[s + 1]].fill(s);
    }
    let up = (0..ns)
        .map(|s| match parent[start[s + 1] - 1] {
            NONE => NONE,
            p => of[p],
        })
        .collect();
    (of, up)
}

/// Liu's elimination tree with path compression, from each group's lower
/// neighbours; `NONE` for a root.
fn elimination_tree(graph: &Graph) -> Vec<usize> {
    let ng = graph.ptr.len() - 1;
    let mut parent = vec![NONE; ng];
    let mut ancestor = vec![NONE; ng];
    for k in 0..ng {
        for &i in graph.of(k) {
            let mut i = i as usize;
            while i != NONE && i < k {
                let next = ancestor[i];
                ancestor[i] = k;
                if next == NONE {
                    parent[i] = k;
                }
                i = next;
            }
        }
    }
    parent
}

/// faer's criterion for a supernodal factor: the flops of the
/// factorisation per entry of `L`, with `degree` below each group.
fn supernodal_pays(weight: impl Fn(usize) -> usize, degree: &[usize]) -> bool {
    let (mut entries, mut flops) = (0.0_f64, 0.0_f64);
    for (g, &d) in degree.iter().enumerate() {
        for c in d + 1..=d + weight(g) {
            let c = c as f64;
            entries += c;
            flops += c + c * (c + 1.0) / 2.0;
        }
    }
    flops / entries > SUPERNODAL_FLOPS_PER_ENTRY
}

/// faer's relaxed amalgamation of the fundamental supernodes (`parent`,
/// `size` in columns, `degree` in rows below the diagonal block): a child
/// numbered just before its parent merges into it while [`RELAX`] allows
/// the zeros it adds. `kept[f]`: `f` ends a relaxed supernode (the ones
/// merged into it precede it).
fn relax(parent: &[usize], size: &[usize], degree: &[usize]) -> Vec<bool> {
    let nf = parent.len();
    let mut size = size.to_vec();
    let mut zeros = vec![0usize; nf];
    let mut merged = vec![false; nf];
    for p in 1..nf {
        let c = p - 1;
        if parent[c] != p || merged[c] {
            continue;
        }
        let new_zeros = (size[p] + degree[p] - degree[c]) * size[c];
        let total = if new_zeros == 0 {
            zeros[p] + zeros[c]
        } else {
            let all = new_zeros + zeros[p] + zeros[c];
            let merged_size = size[c] + size[p];
            let entries = merged_size * (merged_size + 1) / 2 + degree[p] * merged_size;
            match RELAX.iter().find(|&&(max_size, ratio)| {
                max_size >= merged_size && entries as f64 * ratio >= all as f64
            }) {
                Some(_) => all,
                None => continue,
            }
        };
        size[p] += size[c];
        size[c] = 0;
        zeros[p] = total;
        merged[c] = true;
    }
    merged.iter().map(|&m| !m).collect()
}

// ------------------------------------------------------------ plans

/// A disjoint subtree of the supernodal elimination tree: its supernodes
/// and the rows (columns of `L`) they own, both contiguous.
#[derive(Clone, Debug)]
pub(crate) struct Task {
    pub(crate) supernodes: Range<usize>,
    pub(crate) rows: Range<usize>,
}

/// The split of a supernodal factor into parallel subtrees and the
/// supernodes above them; computed once per symbolic analysis.
#[derive(Clone, Debug)]
pub struct SolvePlan {
    pub(crate) tasks: Vec<Task>,
    /// Supernodes outside every task, ascending.
    pub(crate) top: Vec<usize>,
    /// Rows of the top supernodes, ascending.
    pub(crate) top_rows: Vec<usize>,
    /// `top_index[row]`: position of `row` in `top_rows` (`usize::MAX` for
    /// rows inside a task).
    pub(crate) top_index: Vec<usize>,
}

impl SolvePlan {
    /// Splits the tree for `threads` threads: the heaviest subtree (by
    /// entries of `L`) is replaced by its children until there are at least
    /// four tasks per thread and none holds more than a sixteenth of the
    /// factor per thread. One thread, or a tree that is not postordered,
    /// gives a plan with every supernode in the top (a sequential solve).
    pub fn new(symbolic: &Supernodes, threads: usize) -> Self {
        let ns = symbolic.n_supernodes();
        let n = symbolic.nrows();
        let begin = symbolic.supernode_begin();
        let end = symbolic.supernode_end();
        let mut supernode_of = vec![0usize; n];
        for s in 0..ns {
            supernode_of[begin[s]..end[s]].fill(s);
        }
        // parent(s): the supernode of the first row below the diagonal block.
        let parent: Vec<Option<usize>> = (0..ns)
            .map(|s| {
                symbolic
                    .supernode(s)
                    .pattern()
                    .first()
                    .map(|&r| supernode_of[r])
            })
            .collect();
        let own_work: Vec<usize> = (0..ns)
            .map(|s| {
                let size = end[s] - begin[s];
                size * (size + symbolic.supernode(s).pattern().len())
            })
            .collect();
        // Postorder check and subtree sizes: children come before parents and
        // every subtree is the contiguous range [first[s], s].
        let mut first: Vec<usize> = (0..ns).collect();
        let mut count = vec![1usize; ns];
        let mut work = own_work.clone();
        let mut children: Vec<Vec<usize>> = vec![vec![]; ns];
        let mut postordered = true;
        for s in 0..ns {
            if let Some(p) = parent[s] {
                if p <= s {
                    postordered = false;
                    break;
                }
                first[p] = first[p].min(first[s]);
                count[p] += count[s];
                work[p] += work[s];
                children[p].push(s);
            }
        }
        postordered &= (0..ns).all(|s| first[s] + count[s] == s + 1);
        let sequential = Self {
            tasks: vec![],
            top: (0..ns).collect(),
            top_rows: (0..n).collect(),
            top_index: (0..n).collect(),
        };
        if threads < 2 || !postordered || ns == 0 {
            return sequential;
        }
        let total: usize = (0..ns)
            .filter(|&s| parent[s].is_none())
            .map(|s| work[s])
            .sum();
        let mut frontier: Vec<usize> = (0..ns).filter(|&s| parent[s].is_none()).collect();
        let mut top = Vec::new();
        while let Some((pos, &heaviest)) = frontier.iter().enumerate().max_by_key(|(_, &s)| work[s])
        {
            let balanced = frontier.len() >= 4 * threads && work[heaviest] * 16 * threads <= total;
            if balanced || children[heaviest].is_empty() || top.len() > 4096 {
                break;
            }
            frontier.swap_remove(pos);
            top.push(heaviest);
            frontier.extend(&children[heaviest]);
        }
        top.sort_unstable();
        let mut tasks: Vec<Task> = frontier
            .iter()
            .map(|&s| Task {
                supernodes: first[s]..s + 1,
                rows: begin[first[s]]..end[s],
            })
            .collect();
        tasks.sort_by_key(|t| t.rows.start);
        let top_rows: Vec<usize> = top.iter().flat_map(|&s| begin[s]..end[s]).collect();
        let mut top_index = vec![usize::MAX; n];
        for (k, &r) in top_rows.iter().enumerate() {
            top_index[r] = k;
        }
        Self {
            tasks,
            top,
            top_rows,
            top_index,
        }
    }
}

/// Which descendants update which supernode, and the tree of the plan's
/// top; computed once per analysis.
#[derive(Clone, Debug)]
pub(crate) struct UpdatePlan {
    /// `descendants[ptr[s]..ptr[s + 1]]`: the supernodes whose pattern has a
    /// row among the columns of `s`, ascending.
    pub(crate) ptr: Vec<usize>,
    pub(crate) descendants: Vec<u32>,
    /// The top supernodes without a parent in the top.
    pub(crate) top_roots: Vec<usize>,
    /// `top_children[s]`: the children of `s` in the top.
    pub(crate) top_children: Vec<Vec<usize>>,
    /// `work[s]`: multiply-adds of the step of `s` (its descendants'
    /// updates and its own blocks), and their sum: the factorisation's
    /// progress as its supernodes finish.
    pub(crate) work: Vec<f64>,
    pub(crate) total_work: f64,
}

impl UpdatePlan {
    pub(crate) fn new(symbolic: &Supernodes, plan: &SolvePlan) -> Self {
        let ns = symbolic.n_supernodes();
        let begin = symbolic.supernode_begin();
        let end = symbolic.supernode_end();
        let mut supernode_of = vec![0u32; symbolic.nrows()];
        for s in 0..ns {
            supernode_of[begin[s]..end[s]].fill(s as u32);
        }
        // The distinct supernodes of each pattern (sorted rows: runs).
        let supernode_of = &supernode_of;
        let targets = |d: usize| {
            let pattern = symbolic.supernode(d).pattern();
            let mut last = u32::MAX;
            pattern.iter().filter_map(move |&r| {
                let s = supernode_of[r];
                (s != last).then(|| {
                    last = s;
                    s
                })
            })
        };
        let mut count = vec![0usize; ns + 1];
        for d in 0..ns {
            for s in targets(d) {
                count[s as usize + 1] += 1;
            }
        }
        for s in 0..ns {
            count[s + 1] += count[s];
        }
        let ptr = count.clone();
        let mut next = count;
        let mut descendants = vec![0u32; ptr[ns]];
        // A supernode's own blocks: LDL^T of the diagonal block, then the
        // triangular solve of the rows below.
        let mut work: Vec<f64> = (0..ns)
            .map(|s| {
                let (w, below) = (
                    (end[s] - begin[s]) as f64,
                    symbolic.supernode(s).pattern().len() as f64,
                );
                w * w * w / 6.0 + w * w * below / 2.0
            })
            .collect();
        for d in 0..ns {
            let pattern = symbolic.supernode(d).pattern();
            let width = (end[d] - begin[d]) as f64;
            let mut first = 0;
            for s in targets(d) {
                let s = s as usize;
                descendants[next[s]] = d as u32;
                next[s] += 1;
                // The update of d on s: rows from s's first column on, the
                // square of s's own columns as a lower triangle.
                while pattern[first] < begin[s] {
                    first += 1;
                }
                let mid = pattern[first..].partition_point(|&r| r < end[s]) as f64;
                let rows = (pattern.len() - first) as f64;
                work[s] += width * (mid * (mid + 1.0) / 2.0 + (rows - mid) * mid);
            }
        }
        // Whole multiply-adds, so that the last supernode makes 100 %.
        work.iter_mut().for_each(|w| *w = w.floor());
        let total_work = work.iter().sum();
        let mut in_top = vec![false; ns];
        for &s in &plan.top {
            in_top[s] = true;
        }
        let mut top_children: Vec<Vec<usize>> = vec![vec![]; ns];
        let mut top_roots = Vec::new();
        for &s in &plan.top {
            match parent(symbolic, s) {
                Some(p) if in_top[p] => top_children[p].push(s),
                _ => top_roots.push(s),
            }
        }
        Self {
            ptr,
            descendants,
            top_roots,
            top_children,
            work,
            total_work,
        }
    }

    pub(crate) fn of(&self, s: usize) -> &[u32] {
        &self.descendants[self.ptr[s]..self.ptr[s + 1]]
    }
}

/// The supernode of the first row below `s`'s diagonal block.
fn parent(symbolic: &Supernodes, s: usize) -> Option<usize> {
    let row = *symbolic.supernode(s).pattern().first()?;
    let end = symbolic.supernode_end();
    Some(end.partition_point(|&e| e <= row))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ldlt::solve::tests::grid;
    use crate::ldlt::{faer_analysis, SymbolicLdlt};
    use crate::ordering::nested_dissection;
    use crate::sparse::{max_abs, submatrix, symmetric_mul};
    use crate::SparseMat;
    use faer::sparse::linalg::cholesky::{
        CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
    };
    use faer::sparse::linalg::SymbolicSupernodalParams;
    use faer::Mat;

    /// faer's supernodes of `a` in the order `d`, with faer's amalgamation
    /// or without (the exact pattern of `L`).
    fn faers(a: &SparseMat, d: &Dissection, relaxed: bool) -> Supernodes {
        let analysis = if relaxed {
            faer_analysis(a.symbolic(), Some((&d.forward, &d.inverse))).unwrap()
        } else {
            let perm = faer::perm::PermRef::new_checked(&d.forward, &d.inverse, a.nrows());
            let params = CholeskySymbolicParams {
                supernodal_params: SymbolicSupernodalParams { relax: None },
                ..Default::default()
            };
            faer::sparse::linalg::cholesky::factorize_symbolic_cholesky(
                a.symbolic(),
                faer::Side::Lower,
                SymmetricOrdering::Custom(perm),
                params,
            )
            .unwrap()
        };
        let SymbolicCholeskyRaw::Supernodal(s) = analysis.raw() else {
            panic!("a 3D mesh gets a supernodal factor");
        };
        Supernodes::from_faer(s)
    }

    /// The rows of column `j` of `L` below the diagonal.
    fn column(s: &Supernodes, j: usize) -> Vec<usize> {
        let k = s.supernode_end().partition_point(|&e| e <= j);
        (j + 1..s.supernode_end()[k])
            .chain(s.supernode(k).pattern().iter().copied())
            .collect()
    }

    #[test]
    fn the_analysis_on_nodes_is_faers_on_equations() {
        // 3 translations per node of a 10^3-node cube.
        let a = grid(10);
        let order = nested_dissection(a.symbolic()).unwrap();
        let theirs = faers(&a, &order, true);
        // On METIS's graph, and on groups found by hashing.
        let ours = Supernodes::of_dissection(a.symbolic(), &order).unwrap();
        assert!(ours.n_supernodes() > 100);
        assert_eq!(ours, theirs);
        let bare = Dissection::from_order(order.forward.clone(), order.inverse.clone());
        assert_eq!(Supernodes::of_dissection(a.symbolic(), &bare), Some(theirs));
        // Equations of mixed nodes: a third of the nodes keep 2 of their 3
        // translations, every seventh none (as the inner equations of a
        // Craig-Bampton reduction), in the order of all restricted.
        let keep: Vec<usize> = (0..a.nrows())
            .filter(|&i| (i / 3) % 7 != 0 && !((i / 3) % 3 == 1 && i % 3 == 2))
            .collect();
        let kept = submatrix(&a, &keep, &keep);
        let order = order.restricted(&keep);
        let theirs = faers(&kept, &order, true);
        assert_eq!(
            Supernodes::of_dissection(kept.symbolic(), &order),
            Some(theirs.clone())
        );
        let bare = Dissection::from_order(order.forward, order.inverse);
        assert_eq!(
            Supernodes::of_dissection(kept.symbolic(), &bare),
            Some(theirs)
        );
    }

    /// Groups that join equations of different neighbourhoods (what a hash
    /// collision would do) give a pattern with every entry of the exact
    /// one and more, and a factor that still solves the system.
    #[test]
    fn coarser_groups_give_a_larger_pattern_that_still_factorises() {
        let a = grid(8);
        let n = a.nrows();
        let order = nested_dissection(a.symbolic()).unwrap();
        let exact = faers(&a, &order, false);
        let (fine, _) = Groups::hashed(a.symbolic(), &order.forward, &order.inverse);
        // Every second group joins the one before it.
        let mut start: Vec<usize> = fine.start.iter().copied().step_by(2).chain([n]).collect();
        start.dedup();
        let mut of_old = vec![0u32; n];
        for g in 0..start.len() - 1 {
            for p in start[g]..start[g + 1] {
                of_old[order.forward[p]] = g as u32;
            }
        }
        let coarse = Groups { start };
        assert!(coarse.len() < fine.len());
        let graph = coarse.upper_graph(a.symbolic(), &of_old);
        let wide = Supernodes::of_groups(n, &coarse, &graph).unwrap();
        assert!(wide.len_val() > faers(&a, &order, true).len_val());
        for j in 0..n {
            let rows = column(&wide, j);
            let missing = column(&exact, j).into_iter().find(|r| !rows.contains(r));
            assert_eq!(missing, None, "column {j}");
        }
        let symbolic = SymbolicLdlt::with_supernodes(wide, order.forward, order.inverse);
        let mut values = Vec::new();
        symbolic.factorize_into(a.as_ref(), &mut values).unwrap();
        let b = Mat::from_fn(n, 2, |i, j| ((i * 13 + j * 7) % 17) as f64 - 8.0);
        let mut x = b.clone();
        symbolic.solve_in_place(&values, x.as_mut());
        let r = symmetric_mul(&a, x.as_ref()) - &b;
        assert!(max_abs(r.as_ref()) < 1e-10 * max_abs(b.as_ref()));
    }
}
