//! Isosurface stuffing on a body-centred cubic lattice (Labelle & Shewchuk, "Isosurface
//! stuffing: fast tetrahedral meshes with good dihedral angles", SIGGRAPH 2007).
//!
//! The lattice has the corners and the centres of a cubic grid of spacing `h` as vertices;
//! its tetrahedra join the centres of two face-adjacent cubes to an edge of their common face
//! (12 per cube, each of volume h³/12, dihedral angles 60° and 90°). Free space is known only
//! through [`ImplicitDomain`]: its sign at the lattice vertices and the cut points where lattice
//! edges cross its boundary.
//!
//! 1. **Cut points** on every lattice edge whose ends have strictly opposite signs.
//! 2. **Warping**: a vertex with a cut point closer than `α·(edge length)` on one of its edges
//!    ("violated") moves onto the nearest such cut point and is then *on* the boundary; the
//!    cut points on its other edges disappear. The paper's α = 0.24999 on long (axis-parallel)
//!    edges and 0.41189 on short (corner–centre) edges, which with its stencils bound the
//!    dihedral angles in [10.7°, 164.8°] (Labelle & Shewchuk 2007, Table 1).
//! 3. **Stencils**: each lattice tetrahedron with a vertex inside is clipped to free space. The
//!    kept part is a tetrahedron, a pyramid (two tetrahedra) or a triangular prism (three).
//!    Quadrilateral faces are split along the diagonal through their vertex of smallest
//!    global number, so a face shared by two lattice tetrahedra is split the same way on both
//!    sides, and every prism is split into three tetrahedra consistently (Dompierre et al.,
//!    "How to subdivide pyramids, prisms and hexahedra into tetrahedra", 1999). This is simpler
//!    than the paper's parity rule and loses its proven bounds; the angles are measured instead
//!    (see [`crate::QualityReport`]).
//!
//! Faces of the box bounds' lower corner lie on lattice planes, so an axis-aligned box whose
//! coordinates are multiples of `h` from there is meshed exactly (flat faces, sharp edges).

// The stuffing's maps are keyed by vertex numbers: foldhash, not SipHash (whose hashing
// was a twentieth of a configuration space's meshing).
use foldhash::{HashMap, HashMapExt};

use crate::error::VolumeError;
use crate::implicit::ImplicitDomain;
use crate::refine::refine_where;
use crate::solid::{Point, Vector};

/// Warping threshold on long (axis-parallel) lattice edges, from Labelle & Shewchuk (2007).
pub const ALPHA_LONG: f64 = 0.24999;
/// Warping threshold on short (corner–centre) lattice edges, from Labelle & Shewchuk (2007).
pub const ALPHA_SHORT: f64 = 0.41189;

/// Options of [`stuff`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StuffingOptions {
    /// The lattice spacing `h` (cube side); lattice tetrahedra have volume h³/12.
    pub spacing: f64,
    /// Largest number of lattice tetrahedra examined (12 per lattice cube): the mesher refuses
    /// larger lattices before allocating them.
    pub max_tetrahedra: u64,
}

/// The output of [`stuff`]: vertices and positively oriented tetrahedra.
#[derive(Clone, Debug, Default)]
pub struct Stuffed {
    /// Vertex positions (lattice vertices, warped or not, and cut points).
    pub vertices: Vec<Point>,
    /// Tetrahedra, positively oriented.
    pub tetrahedra: Vec<[u32; 4]>,
    /// Number of lattice vertices evaluated.
    pub lattice_vertices: usize,
    /// Number of lattice vertices warped onto the boundary.
    pub warped: usize,
    /// Number of cut points in the output.
    pub cut_points: usize,
    /// Tetrahedra dropped because they were flat (volume below 1e-12·h³).
    pub dropped_flat: usize,
    /// Lattice edges bisected to grade the lattice down to narrow gaps and thin parts
    /// ([`ImplicitDomain::grading`]); 0 on the uniform lattice.
    pub graded: usize,
}

pub(crate) const NONE: u32 = u32::MAX;

/// The lattice: corners `(i, j, k)` for `i ∈ 0..=nx`, then centres `(i, j, k)`, `i ∈ 0..nx`.
pub(crate) struct Lattice {
    pub(crate) n: [usize; 3],
    pub(crate) origin: Point,
    pub(crate) h: f64,
    pub(crate) corners: usize,
}

impl Lattice {
    pub(crate) fn corner(&self, i: usize, j: usize, k: usize) -> u32 {
        (i + (self.n[0] + 1) * (j + (self.n[1] + 1) * k)) as u32
    }
    pub(crate) fn centre(&self, i: usize, j: usize, k: usize) -> u32 {
        (self.corners + i + self.n[0] * (j + self.n[1] * k)) as u32
    }
    pub(crate) fn count(&self) -> usize {
        self.corners + self.n[0] * self.n[1] * self.n[2]
    }
    /// Grid coordinates in half-spacings (corners even, centres odd).
    pub(crate) fn half_coords(&self, v: u32) -> [i64; 3] {
        let v = v as usize;
        if v < self.corners {
            let i = v % (self.n[0] + 1);
            let j = (v / (self.n[0] + 1)) % (self.n[1] + 1);
            let k = v / ((self.n[0] + 1) * (self.n[1] + 1));
            [2 * i as i64, 2 * j as i64, 2 * k as i64]
        } else {
            let c = v - self.corners;
            let i = c % self.n[0];
            let j = (c / self.n[0]) % self.n[1];
            let k = c / (self.n[0] * self.n[1]);
            [2 * i as i64 + 1, 2 * j as i64 + 1, 2 * k as i64 + 1]
        }
    }
    pub(crate) fn at_half(&self, q: [i64; 3]) -> Option<u32> {
        let odd = q[0] & 1;
        if q.iter().any(|&c| c & 1 != odd || c < 0) {
            return None;
        }
        if odd == 0 {
            let [i, j, k] = q.map(|c| (c / 2) as usize);
            (i <= self.n[0] && j <= self.n[1] && k <= self.n[2]).then(|| self.corner(i, j, k))
        } else {
            let [i, j, k] = q.map(|c| (c / 2) as usize);
            (i < self.n[0] && j < self.n[1] && k < self.n[2]).then(|| self.centre(i, j, k))
        }
    }
    pub(crate) fn position(&self, v: u32) -> Point {
        let q = self.half_coords(v);
        // Each coordinate from the origin by an integer multiple of h/2, so lattice planes
        // through the origin's corner are hit exactly.
        Point::new(
            self.origin.x + q[0] as f64 * 0.5 * self.h,
            self.origin.y + q[1] as f64 * 0.5 * self.h,
            self.origin.z + q[2] as f64 * 0.5 * self.h,
        )
    }
    /// The 14 lattice neighbours (6 long, then 8 short) that exist.
    pub(crate) fn neighbours(&self, v: u32) -> impl Iterator<Item = (u32, bool)> + '_ {
        const LONG: [[i64; 3]; 6] = [
            [2, 0, 0],
            [-2, 0, 0],
            [0, 2, 0],
            [0, -2, 0],
            [0, 0, 2],
            [0, 0, -2],
        ];
        const SHORT: [[i64; 3]; 8] = [
            [1, 1, 1],
            [1, 1, -1],
            [1, -1, 1],
            [1, -1, -1],
            [-1, 1, 1],
            [-1, 1, -1],
            [-1, -1, 1],
            [-1, -1, -1],
        ];
        let q = self.half_coords(v);
        LONG.iter()
            .map(|d| (d, true))
            .chain(SHORT.iter().map(|d| (d, false)))
            .filter_map(move |(d, long)| {
                self.at_half([q[0] + d[0], q[1] + d[1], q[2] + d[2]])
                    .map(|w| (w, long))
            })
    }
}

pub(crate) fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The number of lattice tetrahedra [`stuff`] would examine for `bounds` at `spacing`.
pub fn lattice_tetrahedra(bounds: (Point, Point), spacing: f64) -> u64 {
    let d = bounds.1 - bounds.0;
    (0..3)
        .map(|a| ((d[a] / spacing).ceil().max(1.0) as u64).saturating_add(4))
        .fold(12u64, |acc, n| acc.saturating_mul(n))
}

/// Meshes the free space of `domain` by isosurface stuffing (see the module docs).
pub fn stuff(domain: &dyn ImplicitDomain, opts: &StuffingOptions) -> Result<Stuffed, VolumeError> {
    stuff_where(domain, opts, false).map(|(out, _)| out)
}

/// The part of [`stuff`]'s mesh that touches the surface: the stencils of the background
/// tetrahedra with a vertex on or outside it (every face of the full mesh's boundary is a
/// face of one of them), and per output vertex whether it lies on the surface (a cut point
/// or a warped lattice vertex). A face of these tetrahedra that no other of them shares
/// and whose three vertices lie on the surface is a boundary face of the full mesh: a
/// tetrahedron with a surface vertex comes from a background tetrahedron that is kept, so a
/// face with three surface vertices keeps both its sides here; a face that only lost its
/// inner side here has a vertex inside. What the mesher checks against the exact solids
/// before it stuffs the whole domain.
pub(crate) fn stuff_surface(
    domain: &dyn ImplicitDomain,
    opts: &StuffingOptions,
) -> Result<(Stuffed, Vec<bool>), VolumeError> {
    stuff_where(domain, opts, true)
}

/// [`stuff`], of every background tetrahedron or (`surface_only`) of those that touch the
/// surface ([`stuff_surface`]), with per output vertex whether it lies on the surface.
fn stuff_where(
    domain: &dyn ImplicitDomain,
    opts: &StuffingOptions,
    surface_only: bool,
) -> Result<(Stuffed, Vec<bool>), VolumeError> {
    let h = opts.spacing;
    if !(h.is_finite() && h > 0.0) {
        return Err(VolumeError::BadMaxVolume { value: h });
    }
    let bounds = domain.bounds();
    let estimated = lattice_tetrahedra(bounds, h);
    if estimated > opts.max_tetrahedra {
        return Err(VolumeError::TooManyTetrahedra {
            estimated,
            budget: opts.max_tetrahedra,
        });
    }
    let d = bounds.1 - bounds.0;
    let n = [0, 1, 2].map(|a| (d[a] / h).ceil().max(1.0) as usize + 4);
    let lattice = Lattice {
        n,
        origin: bounds.0 - Vector::repeat(2.0 * h),
        h,
        corners: (n[0] + 1) * (n[1] + 1) * (n[2] + 1),
    };
    if lattice.count() >= NONE as usize / 2 {
        return Err(VolumeError::TooManyTetrahedra {
            estimated,
            budget: opts.max_tetrahedra,
        });
    }
    let mut positions: Vec<Point> = (0..lattice.count() as u32)
        .map(|v| lattice.position(v))
        .collect();
    if let Some(grading) = domain.grading(h) {
        let mut tets = Vec::new();
        lattice.for_each_tet(&|_| true, &mut |t| tets.push(t));
        let budget = usize::try_from(opts.max_tetrahedra).unwrap_or(usize::MAX);
        let report = refine_where(
            &mut positions,
            &mut tets,
            &|_| false,
            &*grading.want,
            &*grading.rank,
            budget,
        );
        // (Without a bisection, the positions are the lattice's: stuff it as it is.)
        if report.bisections > 0 {
            let background = Explicit::new(positions, tets);
            let (pos, f, cuts, warped) = cut_and_warp(domain, h, &background.vertices, &|v, k| {
                background.neighbours(v, k)
            });
            let keep = kept(&f, surface_only);
            let (mut out, sources) = emit_over(&pos, &f, &cuts, domain, warped, h, &mut |e| {
                for &t in &background.tets {
                    if keep(&t) {
                        e(t);
                    }
                }
            });
            out.graded = report.bisections;
            return Ok((out, on_surface(&sources, &f, surface_only)));
        }
    }
    let (pos, f, cuts, warped) = cut_and_warp(domain, h, &positions, &|v, k| {
        lattice_neighbours(&lattice, v, k)
    });

    // 3. Stencils over the lattice tetrahedra.
    let keep = kept(&f, surface_only);
    let (out, sources) = emit_over(&pos, &f, &cuts, domain, warped, h, &mut |e| {
        lattice.for_each_tet(&|_| true, &mut |t| {
            if keep(&t) {
                e(t);
            }
        })
    });
    Ok((out, on_surface(&sources, &f, surface_only)))
}

/// Which background tetrahedra [`stuff_where`] stuffs: all, or those with a vertex on or
/// outside the surface.
fn kept(f: &[f64], surface_only: bool) -> impl Fn(&[u32; 4]) -> bool + '_ {
    move |t| !surface_only || t.iter().any(|&v| f[v as usize] >= 0.0)
}

/// Per output vertex of a stuffing, whether it lies on the surface: a cut point, or a
/// lattice vertex whose value is 0 (warped, or on the surface to begin with). Only `asked`
/// (for [`stuff_surface`]); empty otherwise.
fn on_surface(sources: &[Sv], f: &[f64], asked: bool) -> Vec<bool> {
    if !asked {
        return Vec::new();
    }
    sources
        .iter()
        .map(|s| match *s {
            Sv::Cut(..) => true,
            Sv::Lattice(a) => f[a as usize] == 0.0,
        })
        .collect()
}

/// The lattice neighbours of `v`, each with whether the edge is long (axis-parallel).
fn lattice_neighbours(lattice: &Lattice, v: u32, k: &mut dyn FnMut(u32, f64)) {
    for (w, long) in lattice.neighbours(v) {
        k(w, if long { ALPHA_LONG } else { ALPHA_SHORT });
    }
}

/// Lists a vertex's neighbours, each with whether the edge is long (axis-parallel).
type Neighbours<'a> = dyn Fn(u32, &mut dyn FnMut(u32, f64)) + Sync + 'a;

/// Hands every tetrahedron of a background to a callback.
pub(crate) type Tets<'a> = dyn FnMut(&mut dyn FnMut([u32; 4])) + 'a;

/// The ends of the cut edges `edges`, ascending, each once: the only vertices warping can
/// move (it only removes cuts), in the order a pass over every vertex would meet them.
pub(crate) fn cut_ends(edges: impl Iterator<Item = (u32, u32)>) -> Vec<u32> {
    use rayon::prelude::*;
    let mut ends: Vec<u32> = edges.flat_map(|(a, b)| [a, b]).collect();
    ends.par_sort_unstable();
    ends.dedup();
    ends
}

/// The cut points of the edges whose ends have strictly opposite signs.
pub(crate) type Cuts = HashMap<(u32, u32), Point>;

/// Steps 1 and 2 of [`stuff`] over any background mesh with vertices `positions` whose
/// edges `neighbours` lists (with whether each is long, i.e. axis-parallel): the vertices
/// after warping, their signs, the cut points left, and how many vertices were warped.
fn cut_and_warp(
    domain: &dyn ImplicitDomain,
    h: f64,
    positions: &[Point],
    neighbours: &Neighbours<'_>,
) -> (Vec<Point>, Vec<f64>, Cuts, usize) {
    use rayon::prelude::*;
    let nv = positions.len();
    let mut pos = positions.to_vec();
    let zero = 1e-12 * h;
    // The values, and below the cut points, on every core: each is a function of its
    // point (or edge) alone, so the result is the same at any thread count.
    let mut f: Vec<f64> = pos
        .par_iter()
        .map(|p| {
            let v = domain.value(p);
            if v.abs() <= zero { 0.0 } else { v }
        })
        .collect();

    // 1. Cut points on edges with strictly opposite signs.
    let found: Vec<((u32, u32), Point)> = (0..nv as u32)
        .into_par_iter()
        .filter(|&v| f[v as usize] < 0.0)
        .flat_map_iter(|v| {
            let mut here = Vec::new();
            neighbours(v, &mut |w, _| {
                if f[w as usize] > 0.0 {
                    let (a, b) = (&pos[v as usize], &pos[w as usize]);
                    let c = domain.cut(a, f[v as usize], b, f[w as usize]);
                    here.push((key(v, w), c));
                }
            });
            here
        })
        .collect();
    let ends = cut_ends(found.iter().map(|&(e, _)| e));
    let mut cuts: Cuts = found.into_iter().collect();

    // 2. Warping: the threshold is α times the edge's length before any warping.
    let mut warped = 0;
    for v in ends {
        if f[v as usize] == 0.0 {
            continue;
        }
        let mut best: Option<(f64, Point)> = None;
        neighbours(v, &mut |w, alpha| {
            if let Some(c) = cuts.get(&key(v, w)) {
                let dist = (c - pos[v as usize]).norm();
                let len = (positions[w as usize] - positions[v as usize]).norm();
                if dist < alpha * len && best.is_none_or(|(b, _)| dist < b) {
                    best = Some((dist, *c));
                }
            }
        });
        if let Some((_, c)) = best {
            pos[v as usize] = c;
            f[v as usize] = 0.0;
            warped += 1;
            neighbours(v, &mut |w, _| {
                cuts.remove(&key(v, w));
            });
        }
    }
    (pos, f, cuts, warped)
}

/// Step 3 of [`stuff`]: the stencils of every lattice tetrahedron whose first centre `keep`
/// accepts. Also returns, per output vertex, the lattice vertex or edge it came from.
pub(crate) fn emit_stencils(
    lattice: &Lattice,
    pos: &[Point],
    f: &[f64],
    cuts: &HashMap<(u32, u32), Point>,
    domain: &dyn ImplicitDomain,
    warped: usize,
    keep: &dyn Fn([usize; 3]) -> bool,
) -> (Stuffed, Vec<Sv>) {
    emit_over(pos, f, cuts, domain, warped, lattice.h, &mut |e| {
        lattice.for_each_tet(keep, e)
    })
}

/// Step 3 over the tetrahedra `tets` hands out (vertex numbers into `pos`), with, per output
/// vertex, the background vertex or edge it came from.
pub(crate) fn emit_over(
    pos: &[Point],
    f: &[f64],
    cuts: &Cuts,
    domain: &dyn ImplicitDomain,
    warped: usize,
    h: f64,
    tets: &mut Tets<'_>,
) -> (Stuffed, Vec<Sv>) {
    let nv = pos.len();
    let mut out = Stuffed {
        lattice_vertices: nv,
        warped,
        ..Stuffed::default()
    };
    let mut vertex_of = vec![NONE; nv];
    let mut cut_of: HashMap<(u32, u32), u32> = HashMap::new();
    let mut emitter = Emitter {
        pos,
        cuts,
        vertex_of: &mut vertex_of,
        cut_of: &mut cut_of,
        out: &mut out,
        sources: Vec::new(),
        min_volume: 1e-12 * h * h * h,
        nv: nv as u64,
    };
    tets(&mut |t| emitter.stencil(t, f, domain));
    let sources = std::mem::take(&mut emitter.sources);
    (out, sources)
}

impl Lattice {
    /// Hands out every lattice tetrahedron whose first centre `keep` accepts: the two
    /// centres of face-adjacent cubes and an edge of their common face.
    pub(crate) fn for_each_tet(
        &self,
        keep: &dyn Fn([usize; 3]) -> bool,
        emit: &mut dyn FnMut([u32; 4]),
    ) {
        let n = self.n;
        for axis in 0..3 {
            let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut idx = [0usize; 3];
            for k in 0..n[2] {
                for j in 0..n[1] {
                    for i in 0..n[0] {
                        idx[0] = i;
                        idx[1] = j;
                        idx[2] = k;
                        if idx[axis] + 1 >= n[axis] || !keep(idx) {
                            continue;
                        }
                        let c1 = self.centre(i, j, k);
                        let mut up = idx;
                        up[axis] += 1;
                        let c2 = self.centre(up[0], up[1], up[2]);
                        // The shared face's corners, in cyclic order.
                        let corner = |db: usize, dc: usize| {
                            let mut q = idx;
                            q[axis] += 1;
                            q[b] += db;
                            q[c] += dc;
                            self.corner(q[0], q[1], q[2])
                        };
                        let ring = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                        for m in 0..4 {
                            emit([c1, c2, ring[m], ring[(m + 1) % 4]]);
                        }
                    }
                }
            }
        }
    }
}

/// The warping threshold of a graded background's edge `d`: axis-parallel (two coordinates
/// almost zero), the lattice's long-edge α; face and body diagonals, its short-edge one. (The
/// paper's thresholds are for the lattice's own tetrahedra; on the bisected ones between two
/// levels the angles are measured, not bounded.)
pub(crate) fn edge_alpha(d: &Vector) -> f64 {
    let tiny = 1e-9 * d.norm();
    match d.iter().filter(|c| c.abs() <= tiny).count() {
        2 => ALPHA_LONG,
        _ => ALPHA_SHORT,
    }
}

/// A background mesh given by its tetrahedra: a lattice graded by bisection.
struct Explicit {
    vertices: Vec<Point>,
    tets: Vec<[u32; 4]>,
    /// Compressed rows: the neighbours of vertex v are `adjacent[start[v]..start[v + 1]]`.
    start: Vec<usize>,
    adjacent: Vec<(u32, f64)>,
}

impl Explicit {
    fn new(vertices: Vec<Point>, tets: Vec<[u32; 4]>) -> Self {
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(6 * tets.len());
        for t in &tets {
            for i in 0..4 {
                for j in i + 1..4 {
                    edges.push(key(t[i], t[j]));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let nv = vertices.len();
        let mut start = vec![0usize; nv + 1];
        for &(a, b) in &edges {
            start[a as usize + 1] += 1;
            start[b as usize + 1] += 1;
        }
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut adjacent = vec![(0u32, 0.0); start[nv]];
        for &(a, b) in &edges {
            let alpha = edge_alpha(&(vertices[b as usize] - vertices[a as usize]));
            adjacent[fill[a as usize]] = (b, alpha);
            fill[a as usize] += 1;
            adjacent[fill[b as usize]] = (a, alpha);
            fill[b as usize] += 1;
        }
        Explicit {
            vertices,
            tets,
            start,
            adjacent,
        }
    }

    fn neighbours(&self, v: u32, k: &mut dyn FnMut(u32, f64)) {
        for &(w, alpha) in &self.adjacent[self.start[v as usize]..self.start[v as usize + 1]] {
            k(w, alpha);
        }
    }
}

struct Emitter<'a> {
    pos: &'a [Point],
    cuts: &'a HashMap<(u32, u32), Point>,
    vertex_of: &'a mut Vec<u32>,
    cut_of: &'a mut HashMap<(u32, u32), u32>,
    out: &'a mut Stuffed,
    /// Per output vertex: where it came from.
    sources: Vec<Sv>,
    min_volume: f64,
    nv: u64,
}

/// A vertex of a stencil: a lattice vertex or the cut point on a lattice edge.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Sv {
    Lattice(u32),
    Cut(u32, u32),
}

impl Emitter<'_> {
    /// The global number deciding quadrilateral diagonals: lattice vertices first, then cut
    /// points by their edge.
    fn gid(&self, v: Sv) -> u64 {
        match v {
            Sv::Lattice(a) => a as u64,
            Sv::Cut(a, b) => {
                let (a, b) = key(a, b);
                self.nv + (a as u64) * self.nv + b as u64
            }
        }
    }

    fn index(&mut self, v: Sv) -> u32 {
        match v {
            Sv::Lattice(a) => {
                let slot = &mut self.vertex_of[a as usize];
                if *slot == NONE {
                    *slot = self.out.vertices.len() as u32;
                    self.out.vertices.push(self.pos[a as usize]);
                    self.sources.push(v);
                }
                *slot
            }
            Sv::Cut(a, b) => {
                let k = key(a, b);
                if let Some(&i) = self.cut_of.get(&k) {
                    return i;
                }
                let i = self.out.vertices.len() as u32;
                // Present by construction: both ends keep strict opposite signs.
                let p = self.cuts.get(&k).copied().unwrap_or_else(|| {
                    nalgebra::center(&self.pos[a as usize], &self.pos[b as usize])
                });
                self.out.vertices.push(p);
                self.sources.push(v);
                self.out.cut_points += 1;
                self.cut_of.insert(k, i);
                i
            }
        }
    }

    fn emit(&mut self, t: [Sv; 4]) {
        let mut ids = t.map(|v| self.index(v));
        let p = ids.map(|i| self.out.vertices[i as usize]);
        let vol = (p[1] - p[0]).dot(&(p[2] - p[0]).cross(&(p[3] - p[0])));
        if vol.abs() <= 6.0 * self.min_volume {
            self.out.dropped_flat += 1;
            return;
        }
        if vol < 0.0 {
            ids.swap(2, 3);
        }
        self.out.tetrahedra.push(ids);
    }

    /// Prism with triangles `a` and `b`, lateral edges `a[i]–b[i]`.
    fn prism(&mut self, a: [Sv; 3], b: [Sv; 3]) {
        let all = [a[0], a[1], a[2], b[0], b[1], b[2]];
        let g: Vec<u64> = all.iter().map(|&v| self.gid(v)).collect();
        let m = (0..6).min_by_key(|&i| g[i]).unwrap_or(0);
        let (mut a, mut b, mut ga, mut gb) = (a, b, [g[0], g[1], g[2]], [g[3], g[4], g[5]]);
        let mut r = m;
        if m >= 3 {
            std::mem::swap(&mut a, &mut b);
            std::mem::swap(&mut ga, &mut gb);
            r = m - 3;
        }
        let rot = |x: [Sv; 3]| [x[r], x[(r + 1) % 3], x[(r + 2) % 3]];
        let rotg = |x: [u64; 3]| [x[r], x[(r + 1) % 3], x[(r + 2) % 3]];
        let (a, b, ga, gb) = (rot(a), rot(b), rotg(ga), rotg(gb));
        if ga[1].min(gb[2]) < ga[2].min(gb[1]) {
            self.emit([a[0], a[1], a[2], b[2]]);
            self.emit([a[0], a[1], b[2], b[1]]);
            self.emit([a[0], b[1], b[2], b[0]]);
        } else {
            self.emit([a[0], a[1], a[2], b[1]]);
            self.emit([a[0], b[1], a[2], b[2]]);
            self.emit([a[0], b[1], b[2], b[0]]);
        }
    }

    /// Pyramid over the quadrilateral `q` (cyclic) with apex `z`.
    fn pyramid(&mut self, q: [Sv; 4], z: Sv) {
        let g = q.map(|v| self.gid(v));
        let m = (0..4).min_by_key(|&i| g[i]).unwrap_or(0);
        if m % 2 == 0 {
            self.emit([q[0], q[1], q[2], z]);
            self.emit([q[0], q[2], q[3], z]);
        } else {
            self.emit([q[1], q[2], q[3], z]);
            self.emit([q[1], q[3], q[0], z]);
        }
    }

    fn stencil(&mut self, tet: [u32; 4], f: &[f64], domain: &dyn ImplicitDomain) {
        let (mut neg, mut zer, mut pos) = ([0u32; 4], [0u32; 4], [0u32; 4]);
        let (mut nn, mut nz, mut np) = (0, 0, 0);
        for &v in &tet {
            let s = f[v as usize];
            if s < 0.0 {
                neg[nn] = v;
                nn += 1;
            } else if s > 0.0 {
                pos[np] = v;
                np += 1;
            } else {
                zer[nz] = v;
                nz += 1;
            }
        }
        let l = Sv::Lattice;
        let c = Sv::Cut;
        match (nn, nz, np) {
            (0, 4, 0) => {
                let centroid = Point::from(
                    tet.iter()
                        .map(|&v| self.pos[v as usize].coords)
                        .sum::<Vector>()
                        / 4.0,
                );
                if domain.value(&centroid) < 0.0 {
                    self.emit(tet.map(l));
                }
            }
            (0, _, _) => {}
            (_, _, 0) => self.emit(tet.map(l)),
            (1, 0, 3) => self.emit([
                l(neg[0]),
                c(neg[0], pos[0]),
                c(neg[0], pos[1]),
                c(neg[0], pos[2]),
            ]),
            (1, 1, 2) => self.emit([l(neg[0]), l(zer[0]), c(neg[0], pos[0]), c(neg[0], pos[1])]),
            (1, 2, 1) => self.emit([l(neg[0]), l(zer[0]), l(zer[1]), c(neg[0], pos[0])]),
            (2, 0, 2) => self.prism(
                [l(neg[0]), c(neg[0], pos[0]), c(neg[0], pos[1])],
                [l(neg[1]), c(neg[1], pos[0]), c(neg[1], pos[1])],
            ),
            (2, 1, 1) => self.pyramid(
                [l(neg[0]), l(neg[1]), c(neg[1], pos[0]), c(neg[0], pos[0])],
                l(zer[0]),
            ),
            (3, 0, 1) => self.prism(
                [l(neg[0]), l(neg[1]), l(neg[2])],
                [c(neg[0], pos[0]), c(neg[1], pos[0]), c(neg[2], pos[0])],
            ),
            _ => {}
        }
    }
}
