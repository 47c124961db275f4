//! Isosurface stuffing of a domain that is periodic along some axes (a configuration space's
//! angles: a rigid robot's heading θ, an arm's unlimited joints), and the two meshes a
//! periodic mesh is used through.
//!
//! **The lattice closes on itself.** Along a periodic axis the lattice has exactly `N` cells
//! of the spacing `h`, so the period is `L = N·h`, and lattice vertex `k` and `k + N` (in cells)
//! are one vertex. Signs, cut points and warping are computed once per such class on its
//! *canonical* member (index in `0..N`) with the neighbourhood wrapped around, so every copy
//! of a vertex is warped the same way and every copy of an edge is cut at the same point.
//! The stencils are then emitted for one representative of every class of lattice
//! tetrahedra (those whose first centre has a canonical index), each with its vertices
//! *unwrapped* next to it, so every tetrahedron keeps its true shape. The output — the
//! **slab** — is a conforming tetrahedral mesh of one period whose two ends are the same
//! jagged surface, one a translate of the other by `L`; [`PeriodicStuffed::orbit`] names, per
//! output vertex, the class it belongs to, and [`PeriodicStuffed::wrap`] its period offset.
//!
//! * [`PeriodicMesh::slab`] is that period as a [`TetMesh`]; its end faces are tagged
//!   `Obstacle(`[`SEAM_PART`]`)` and [`PeriodicMesh::images`] maps every vertex to the one
//!   it is identified with, which is how the FEM folds the system (`harmonic_fem::volume`'s
//!   `identify_periodic`): the ends carry no condition of their own and every pair of
//!   identified vertices is one unknown, so the discrete potential is exactly periodic.
//! * [`PeriodicMesh::covering`] is `2c + 1` copies of the slab laid end to end along every
//!   periodic axis and glued (a finite piece of the universal cover), on which a tracer
//!   follows the periodic potential with the angles unwrapped: a path crosses θ = 2π as any
//!   other face. Its adjacency is the slab's, copied, with each seam face joined to its
//!   partner (the face at the other end whose corners are of the same classes) in the
//!   neighbouring copy: only the slab's faces are ever sorted.

// The stuffing's maps are keyed by vertex numbers: foldhash, not SipHash (whose hashing
// was a twentieth of a configuration space's meshing).
use foldhash::{HashMap, HashMapExt};

use harmonic_types::{BoundaryTag, SEAM_PART};

use crate::error::VolumeError;
use crate::implicit::ImplicitDomain;
use crate::refine::{PeriodicTets, offset, refine_periodic};
use crate::solid::{Point, Vector};
use crate::stuffing::{
    ALPHA_LONG, ALPHA_SHORT, Cuts, Lattice, NONE, Stuffed, StuffingOptions, Sv, edge_alpha,
    emit_over, emit_stencils, key,
};
use harmonic_types::EDGES;
use harmonic_types::{NO_NEIGHBOR, TetMesh};

/// The output of [`stuff_periodic`].
#[derive(Clone, Debug, Default)]
pub struct PeriodicStuffed {
    /// The slab: vertices (unwrapped, each tetrahedron with its true shape) and tetrahedra.
    pub stuffed: Stuffed,
    /// Per output vertex: its class (vertices of one class are one vertex of the periodic
    /// mesh).
    pub orbit: Vec<u32>,
    /// Per output vertex: its offset from its class's canonical position, in periods.
    pub wrap: Vec<[i32; 3]>,
    /// The period along each axis (`None`: not periodic).
    pub period: [Option<f64>; 3],
}

/// The number of lattice tetrahedra [`stuff_periodic`] examines.
pub fn periodic_lattice_tetrahedra(
    bounds: (Point, Point),
    spacing: f64,
    cells: [Option<usize>; 3],
) -> u64 {
    let d = bounds.1 - bounds.0;
    (0..3)
        .map(|a| match cells[a] {
            Some(c) => c as u64 + 1,
            None => ((d[a] / spacing).ceil().max(1.0) as u64).saturating_add(4),
        })
        .fold(12u64, |acc, n| acc.saturating_mul(n))
}

/// Half-coordinate offsets of the 6 long and 8 short lattice edges.
const STEPS: [([i64; 3], bool); 14] = [
    ([2, 0, 0], true),
    ([-2, 0, 0], true),
    ([0, 2, 0], true),
    ([0, -2, 0], true),
    ([0, 0, 2], true),
    ([0, 0, -2], true),
    ([1, 1, 1], false),
    ([1, 1, -1], false),
    ([1, -1, 1], false),
    ([1, -1, -1], false),
    ([-1, 1, 1], false),
    ([-1, 1, -1], false),
    ([-1, -1, 1], false),
    ([-1, -1, -1], false),
];

struct Wrapped<'a> {
    lattice: &'a Lattice,
    cells: [Option<usize>; 3],
    period: [Option<f64>; 3],
}

impl Wrapped<'_> {
    /// The canonical vertex of `q` (half coordinates, any integers) and its offset in periods,
    /// or `None` off the lattice along a non-periodic axis.
    fn canonical_half(&self, mut q: [i64; 3]) -> Option<(u32, [i32; 3])> {
        let mut w = [0i32; 3];
        for a in 0..3 {
            if let Some(c) = self.cells[a] {
                let p = 2 * c as i64;
                w[a] = q[a].div_euclid(p) as i32;
                q[a] = q[a].rem_euclid(p);
            }
        }
        self.lattice.at_half(q).map(|v| (v, w))
    }
    fn canonical(&self, v: u32) -> (u32, [i32; 3]) {
        self.canonical_half(self.lattice.half_coords(v))
            .unwrap_or((v, [0; 3]))
    }
    fn offset(&self, w: [i32; 3]) -> Vector {
        offset(self.period, w)
    }
    /// The 14 neighbours of `v` around the periodic axes: (canonical vertex, long edge,
    /// its offset in periods relative to `v`'s frame).
    fn neighbours(&self, v: u32) -> impl Iterator<Item = (u32, bool, [i32; 3])> + '_ {
        let q = self.lattice.half_coords(v);
        STEPS.iter().filter_map(move |(d, long)| {
            self.canonical_half([q[0] + d[0], q[1] + d[1], q[2] + d[2]])
                .map(|(w, s)| (w, *long, s))
        })
    }
}

/// Isosurface stuffing of `domain`, periodic along every axis `a` with `cells[a] = Some(N)`:
/// there the domain must be periodic with period `N·spacing`, starting at its bounds' lower
/// coordinate, and `N ≥ 3` (see the module docs).
pub fn stuff_periodic(
    domain: &(dyn ImplicitDomain + Sync),
    opts: &StuffingOptions,
    cells: [Option<usize>; 3],
) -> Result<PeriodicStuffed, VolumeError> {
    let h = opts.spacing;
    if !(h.is_finite() && h > 0.0) {
        return Err(VolumeError::BadMaxVolume { value: h });
    }
    if let Some(c) = cells.iter().flatten().find(|&&c| c < 3) {
        return Err(VolumeError::PeriodicCells { cells: *c });
    }
    let bounds = domain.bounds();
    let estimated = periodic_lattice_tetrahedra(bounds, h, cells);
    if estimated > opts.max_tetrahedra {
        return Err(VolumeError::TooManyTetrahedra {
            estimated,
            budget: opts.max_tetrahedra,
        });
    }
    let d = bounds.1 - bounds.0;
    let mut n = [0usize; 3];
    let mut origin = bounds.0 - Vector::repeat(2.0 * h);
    for a in 0..3 {
        match cells[a] {
            Some(c) => {
                n[a] = c + 1;
                origin[a] = bounds.0[a];
            }
            None => n[a] = (d[a] / h).ceil().max(1.0) as usize + 4,
        }
    }
    let lattice = Lattice {
        n,
        origin,
        h,
        corners: (n[0] + 1) * (n[1] + 1) * (n[2] + 1),
    };
    if lattice.count() >= NONE as usize / 2 {
        return Err(VolumeError::TooManyTetrahedra {
            estimated,
            budget: opts.max_tetrahedra,
        });
    }
    let period_of = [0, 1, 2].map(|a| cells[a].map(|c| c as f64 * h));
    let wrapped = Wrapped {
        lattice: &lattice,
        cells,
        period: period_of,
    };
    let nv = lattice.count();
    let canon: Vec<(u32, [i32; 3])> = (0..nv as u32).map(|v| wrapped.canonical(v)).collect();
    let positions: Vec<Point> = (0..nv as u32).map(|v| lattice.position(v)).collect();
    // One lattice tetrahedron per class: its first centre canonical.
    let keep = |idx: [usize; 3]| (0..3).all(|a| cells[a].is_none_or(|c| idx[a] < c));

    if let Some(grading) = domain.grading(h) {
        // The lattice's tetrahedra of one period as a quotient mesh, graded by bisection.
        let mut background = PeriodicTets {
            vertices: positions.clone(),
            period: period_of,
            origin: lattice.origin,
            ..PeriodicTets::default()
        };
        lattice.for_each_tet(&keep, &mut |t| {
            background.tets.push(t.map(|v| canon[v as usize].0));
            background.wraps.push(t.map(|v| canon[v as usize].1));
        });
        let budget = usize::try_from(opts.max_tetrahedra).unwrap_or(usize::MAX);
        let report = refine_periodic(&mut background, &*grading.want, &*grading.rank, budget);
        if report.bisections > 0 {
            let mut out = stuff_quotient(domain, h, &background, grading.known.as_deref());
            out.stuffed.graded = report.bisections;
            return Ok(out);
        }
    }

    // 1–2. Cut points and warping on the canonical vertices, their neighbourhoods wrapped.
    let is_canonical = |v: u32| canon[v as usize].0 == v;
    let active: Vec<u32> = (0..nv as u32).filter(|&v| is_canonical(v)).collect();
    let (pos, f, cuts, warped) = cut_and_warp_quotient(
        domain,
        None,
        h,
        &positions,
        &active,
        &|v, k| {
            for (w, long, s) in wrapped.neighbours(v) {
                k(w, if long { ALPHA_LONG } else { ALPHA_SHORT }, s);
            }
        },
        period_of,
    );

    // The unwrapped lattice: every copy where its class's canonical member is, shifted.
    let mut f_ext = vec![0.0; nv];
    let mut pos_ext = pos.clone();
    for v in 0..nv {
        let (c, w) = canon[v];
        f_ext[v] = f[c as usize];
        pos_ext[v] = pos[c as usize] + wrapped.offset(w);
    }
    let mut cuts_ext: HashMap<(u32, u32), Point> = HashMap::new();
    for e in 0..nv as u32 {
        if f_ext[e as usize] >= 0.0 {
            continue;
        }
        for (x, _) in lattice.neighbours(e) {
            if f_ext[x as usize] <= 0.0 {
                continue;
            }
            let ((ce, we), (cx, wx)) = (canon[e as usize], canon[x as usize]);
            if let Some(c) = cuts.get(&key(ce, cx)) {
                let w = if ce < cx { we } else { wx };
                cuts_ext.insert(key(e, x), c + wrapped.offset(w));
            }
        }
    }

    // 3. Stencils of one lattice tetrahedron per class.
    let (stuffed, sources) =
        emit_stencils(&lattice, &pos_ext, &f_ext, &cuts_ext, domain, warped, &keep);
    let (orbit, wrap) = classes(&sources, &|e| canon[e as usize]);
    Ok(PeriodicStuffed {
        stuffed,
        orbit,
        wrap,
        period: period_of,
    })
}

/// Values a grading already computed, by point ([`crate::Grading::known`]).
type Known<'a> = crate::implicit::KnownValues<'a>;

/// Lists a canonical vertex's neighbours: (neighbour, warping threshold α, the neighbour's
/// offset in periods relative to the vertex's frame).
type QuotientNeighbours<'a> = dyn Fn(u32, &mut dyn FnMut(u32, f64, [i32; 3])) + 'a;

/// A free lattice vertex whose edges are cut on opposite sides (two cut points more than
/// 120° apart as seen from it) lies in a passage thinner than the lattice; warped onto one
/// wall, it leaves the passage with no vertex inside, and tetrahedra whose four vertices all
/// lie on the walls carry no flow (a 2 × 0.3 bar through a 0.85 slot in a 0.4 wall, at the
/// default spacing of a configuration space: ψ = 0 behind the slot, every start stalled). Such
/// a vertex is not warped when it is free by more than this fraction of the spacing; the
/// tetrahedra around it keep a short edge to the cut point instead (their angles are
/// measured, and the planning solve clamps). Kept for every such vertex, shallower ones
/// included, the rule opened passages so thin that the mesh's chords cut across their walls:
/// two seeded 3-link arms' paths came back `collision`.
pub(crate) const THIN_FREE_DEPTH: f64 = 0.2;

/// Steps 1 and 2 of stuffing on the canonical vertices `active` (ascending) of a periodic
/// background (positions `positions`, edges `neighbours`; values from `known` where it has
/// them, else from the domain): the vertices after warping, their signs, the cut points
/// left (each in the frame of its edge's lower-numbered end) and how many vertices were
/// warped. Every copy of a vertex is warped alike and every copy of an edge cut
/// at the same point, because each is computed once, on its class.
fn cut_and_warp_quotient(
    domain: &(dyn ImplicitDomain + Sync),
    known: Option<&Known<'_>>,
    h: f64,
    positions: &[Point],
    active: &[u32],
    neighbours: &QuotientNeighbours<'_>,
    period: [Option<f64>; 3],
) -> (Vec<Point>, Vec<f64>, Cuts, usize) {
    use rayon::prelude::*;
    let mut pos = positions.to_vec();
    let zero = 1e-12 * h;
    let mut f = vec![0.0f64; positions.len()];
    let values: Vec<f64> = active
        .par_iter()
        .map(|&v| {
            let p = &pos[v as usize];
            let x = known.and_then(|k| k(p)).unwrap_or_else(|| domain.value(p));
            if x.abs() <= zero { 0.0 } else { x }
        })
        .collect();
    for (&v, x) in active.iter().zip(values) {
        f[v as usize] = x;
    }

    // 1. Cut points on edges with strictly opposite signs, each stored in the frame of its
    //    lower-numbered end.
    let mut edges: Vec<(u32, u32, [i32; 3])> = Vec::new();
    for &v in active {
        if f[v as usize] < 0.0 {
            neighbours(v, &mut |w, _, s| {
                if f[w as usize] > 0.0 {
                    edges.push((v, w, s));
                }
            });
        }
    }
    let found: Vec<((u32, u32), Point)> = edges
        .par_iter()
        .map(|&(v, w, s)| {
            let (a, b) = (pos[v as usize], pos[w as usize] + offset(period, s));
            let c = domain.cut(&a, f[v as usize], &b, f[w as usize]);
            let c = if v < w { c } else { c - offset(period, s) };
            (key(v, w), c)
        })
        .collect();
    let mut cuts: Cuts = found.into_iter().collect();

    // 2. Warping: the threshold is α times the edge's length before any warping; only the
    //    ends of cut edges, in increasing order as `active` lists them.
    let ends = crate::stuffing::cut_ends(cuts.keys().copied());
    let mut warped = 0;
    let mut seen: Vec<crate::solid::Vector> = Vec::new();
    for &v in &ends {
        if f[v as usize] == 0.0 {
            continue;
        }
        let mut best: Option<(f64, Point)> = None;
        // Whether two cut points lie on opposite sides of a free `v` (more than 120° apart).
        let free = f[v as usize] < 0.0;
        seen.clear();
        let mut thin = false;
        neighbours(v, &mut |w, alpha, s| {
            if let Some(c) = cuts.get(&key(v, w)) {
                let c = if v < w { *c } else { c + offset(period, s) };
                let dist = (c - pos[v as usize]).norm();
                if free && dist > 0.0 {
                    let d = (c - pos[v as usize]) / dist;
                    thin |= seen.iter().any(|e| e.dot(&d) < -0.5);
                    seen.push(d);
                }
                let len =
                    (positions[w as usize] + offset(period, s) - positions[v as usize]).norm();
                if dist < alpha * len && best.is_none_or(|(b, _)| dist < b) {
                    best = Some((dist, c));
                }
            }
        });
        // A free vertex inside a passage thinner than the lattice stays where it is (see
        // `THIN_FREE_DEPTH`).
        let keep = thin && f[v as usize] < -THIN_FREE_DEPTH * h;
        if let Some((_, c)) = best.filter(|_| !keep) {
            pos[v as usize] = c;
            f[v as usize] = 0.0;
            warped += 1;
            neighbours(v, &mut |w, _, _| {
                cuts.remove(&key(v, w));
            });
        }
    }
    (pos, f, cuts, warped)
}

/// Stuffing over a graded quotient background (see [`refine_periodic`]): cut points and
/// warping on its canonical vertices, then the stencils of its tetrahedra over the copies
/// of the vertices they use (vertex `c` shifted `w` periods is one output copy).
fn stuff_quotient(
    domain: &(dyn ImplicitDomain + Sync),
    h: f64,
    background: &PeriodicTets,
    known: Option<&Known<'_>>,
) -> PeriodicStuffed {
    use rayon::prelude::*;
    let period = background.period;
    let nv = background.vertices.len();
    // The quotient's edges, each once: (a, b, b's offset from a), a < b, found per vertex
    // among the tetrahedra around it, a run of vertices per task (on every core).
    let around = harmonic_types::Grouped::tets_around(nv, &background.tets);
    let edges: Vec<(u32, u32, [i32; 3])> = harmonic_types::vertex_runs(nv)
        .into_par_iter()
        .map(|(first, end)| {
            let (mut out, mut list) = (Vec::new(), Vec::<(u32, [i32; 3])>::new());
            for a in first as u32..end as u32 {
                list.clear();
                for &t in around.of(a as usize) {
                    let (tet, w) = (background.tets[t as usize], background.wraps[t as usize]);
                    let ia = tet.iter().position(|&v| v == a).unwrap_or(0);
                    for j in 0..4 {
                        if tet[j] > a {
                            list.push((tet[j], [0, 1, 2].map(|k| w[j][k] - w[ia][k])));
                        }
                    }
                }
                list.sort_unstable_by_key(|&(b, _)| b);
                list.dedup_by_key(|&mut (b, _)| b);
                out.extend(list.iter().map(|&(b, rel)| (a, b, rel)));
            }
            out
        })
        .collect::<Vec<_>>()
        .concat();
    let used: Vec<bool> = (0..nv).map(|v| !around.of(v).is_empty()).collect();
    let mut start = vec![0usize; nv + 1];
    for &(a, b, _) in &edges {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut adjacent = vec![(0u32, 0.0f64, [0i32; 3]); start[nv]];
    for &(a, b, rel) in &edges {
        let d = background.vertices[b as usize] + background.offset(rel)
            - background.vertices[a as usize];
        let alpha = edge_alpha(&d);
        adjacent[fill[a as usize]] = (b, alpha, rel);
        fill[a as usize] += 1;
        adjacent[fill[b as usize]] = (a, alpha, rel.map(|x| -x));
        fill[b as usize] += 1;
    }
    let active: Vec<u32> = (0..nv as u32).filter(|&v| used[v as usize]).collect();
    let (pos, f, cuts, warped) = cut_and_warp_quotient(
        domain,
        known,
        h,
        &background.vertices,
        &active,
        &|v, k| {
            for &(w, alpha, s) in &adjacent[start[v as usize]..start[v as usize + 1]] {
                k(w, alpha, s);
            }
        },
        period,
    );

    // The copies the tetrahedra use, numbered in the order of (class, shift): two copies of a
    // face then order their corners alike, and split their quadrilaterals alike.
    let mut keys: Vec<u64> = background
        .tets
        .par_iter()
        .zip(&background.wraps)
        .flat_map_iter(|(tet, w)| (0..4).map(move |i| (tet[i] as u64) << 32 | pack(w[i]) as u64))
        .collect();
    keys.par_sort_unstable();
    keys.dedup();
    // Each class's copies are a run of the sorted keys, a few long: found from the run's
    // start instead of by a search over all of them.
    let mut first = vec![0u32; nv + 1];
    {
        let mut i = 0usize;
        for (c, slot) in first.iter_mut().enumerate() {
            while i < keys.len() && ((keys[i] >> 32) as usize) < c {
                i += 1;
            }
            *slot = i as u32;
        }
    }
    let id = |c: u32, w: [i32; 3]| {
        let k = (c as u64) << 32 | pack(w) as u64;
        let run = &keys[first[c as usize] as usize..first[c as usize + 1] as usize];
        first[c as usize] + run.iter().position(|&x| x == k).unwrap_or(0) as u32
    };
    let copies: Vec<(u32, [i32; 3])> = keys
        .iter()
        .map(|&k| ((k >> 32) as u32, unpack(k as u32)))
        .collect();
    let pos_ext: Vec<Point> = copies
        .iter()
        .map(|&(c, w)| pos[c as usize] + background.offset(w))
        .collect();
    let f_ext: Vec<f64> = copies.iter().map(|&(c, _)| f[c as usize]).collect();
    let tets: Vec<[u32; 4]> = background
        .tets
        .par_iter()
        .zip(&background.wraps)
        .map(|(tet, w)| [0, 1, 2, 3].map(|i| id(tet[i], w[i])))
        .collect();
    let mut cuts_ext: Cuts = HashMap::new();
    for t in &tets {
        for [i, j] in EDGES {
            let (e, x) = if f_ext[t[i] as usize] < 0.0 {
                (t[i], t[j])
            } else {
                (t[j], t[i])
            };
            if !(f_ext[e as usize] < 0.0 && f_ext[x as usize] > 0.0) {
                continue;
            }
            let ((ce, we), (cx, wx)) = (copies[e as usize], copies[x as usize]);
            if let Some(c) = cuts.get(&key(ce, cx)) {
                let w = if ce < cx { we } else { wx };
                cuts_ext.insert(key(e, x), c + background.offset(w));
            }
        }
    }
    let (stuffed, sources) = emit_over(&pos_ext, &f_ext, &cuts_ext, domain, warped, h, &mut |e| {
        for &t in &tets {
            e(t);
        }
    });
    let (orbit, wrap) = classes(&sources, &|e| copies[e as usize]);
    PeriodicStuffed {
        stuffed,
        orbit,
        wrap,
        period,
    }
}

/// A shift in periods as one integer whose order is the shifts' order (each component in
/// −128..128; a mesh's shifts are a few periods at most).
fn pack(w: [i32; 3]) -> u32 {
    w.iter()
        .fold(0u32, |acc, &c| acc << 8 | (c + 128).clamp(0, 255) as u32)
}

/// The shift [`pack`] packed.
fn unpack(k: u32) -> [i32; 3] {
    [16, 8, 0].map(|s| ((k >> s) & 0xFF) as i32 - 128)
}

/// The class of every output vertex and its offset in periods, from where it came from
/// (`canon` gives a background vertex's class and shift): a background vertex's class, or
/// the class of the edge a cut point lies on (in the frame of its lower class).
fn classes(sources: &[Sv], canon: &dyn Fn(u32) -> (u32, [i32; 3])) -> (Vec<u32>, Vec<[i32; 3]>) {
    #[derive(Hash, PartialEq, Eq)]
    enum Class {
        Lattice(u32),
        Cut(u32, u32),
    }
    let mut class_of: HashMap<Class, u32> = HashMap::new();
    let mut orbit = Vec::with_capacity(sources.len());
    let mut wrap = Vec::with_capacity(sources.len());
    for s in sources {
        let (class, w) = match *s {
            Sv::Lattice(e) => {
                let (c, w) = canon(e);
                (Class::Lattice(c), w)
            }
            Sv::Cut(a, b) => {
                let ((ca, wa), (cb, wb)) = (canon(a), canon(b));
                if ca < cb {
                    (Class::Cut(ca, cb), wa)
                } else {
                    (Class::Cut(cb, ca), wb)
                }
            }
        };
        let next = class_of.len() as u32;
        orbit.push(*class_of.entry(class).or_insert(next));
        wrap.push(w);
    }
    (orbit, wrap)
}

/// A mesh of a periodic domain: the slab of one period for the FEM and a covering of
/// several periods for tracing (see the module docs).
#[derive(Debug)]
pub struct PeriodicMesh {
    /// One period; its end faces are tagged `Obstacle(`[`SEAM_PART`]`)`.
    pub slab: TetMesh,
    /// Per slab vertex: the slab vertex it is identified with (itself for one member of
    /// every class).
    pub images: Vec<u32>,
    /// `2·copies + 1` periods along every periodic axis, glued; the middle copy is the slab.
    pub covering: TetMesh,
    /// Per covering vertex: a slab vertex of its class.
    pub slab_vertex: Vec<u32>,
    /// The period along each axis.
    pub period: [Option<f64>; 3],
    /// The copies on each side of the slab in the covering.
    pub copies: i32,
    /// Slab end faces (each end counted).
    pub seam_faces: usize,
}

impl PeriodicMesh {
    /// Builds both meshes from stuffing output; boundary faces are tagged by `tag` (the
    /// domain's), the slab's ends by [`SEAM_PART`].
    pub fn new(
        stuffed: &PeriodicStuffed,
        copies: i32,
        tag: &(dyn Fn(&Point) -> BoundaryTag + Sync),
    ) -> Result<PeriodicMesh, VolumeError> {
        let s = &stuffed.stuffed;
        let periodic: Vec<usize> = (0..3).filter(|&a| stuffed.period[a].is_some()).collect();
        // Representative of each class: its first vertex.
        let classes = stuffed
            .orbit
            .iter()
            .copied()
            .max()
            .map_or(0, |m| m as usize + 1);
        let mut rep = vec![NONE; classes];
        for (v, &o) in stuffed.orbit.iter().enumerate() {
            if rep[o as usize] == NONE {
                rep[o as usize] = v as u32;
            }
        }
        let images: Vec<u32> = stuffed.orbit.iter().map(|&o| rep[o as usize]).collect();

        // The covering: copies c along every periodic axis.
        let mut shifts: Vec<[i32; 3]> = vec![[0; 3]];
        for &a in &periodic {
            let mut next = Vec::new();
            for sh in &shifts {
                for c in -copies..=copies {
                    let mut t = *sh;
                    t[a] = c;
                    next.push(t);
                }
            }
            shifts = next;
        }
        // One covering vertex per (class, periods from the class's canonical member): the
        // slab's vertices in every copy, numbered in the order of those keys.
        use rayon::prelude::*;
        let nsv = s.vertices.len();
        let key = |v: usize, sh: &[i32; 3]| {
            let w = stuffed.wrap[v];
            (stuffed.orbit[v] as u64) << 32
                | pack([w[0] + sh[0], w[1] + sh[1], w[2] + sh[2]]) as u64
        };
        let keys: Vec<u64> = shifts
            .iter()
            .flat_map(|sh| (0..nsv).map(move |v| key(v, sh)))
            .collect();
        let mut unique = keys.clone();
        unique.par_sort_unstable();
        unique.dedup();
        let ids: Vec<u32> = keys
            .par_iter()
            .map(|k| unique.binary_search(k).unwrap_or(0) as u32)
            .collect();
        let mut vertices = vec![Point::origin(); unique.len()];
        let mut slab_vertex = vec![NONE; unique.len()];
        for (c, sh) in shifts.iter().enumerate() {
            for v in 0..nsv {
                let id = ids[c * nsv + v] as usize;
                if slab_vertex[id] == NONE {
                    vertices[id] = s.vertices[v] + offset(stuffed.period, *sh);
                    slab_vertex[id] = v as u32;
                }
            }
        }
        let mut tets: Vec<[u32; 4]> = Vec::with_capacity(shifts.len() * s.tetrahedra.len());
        for c in 0..shifts.len() {
            let ids = &ids[c * nsv..(c + 1) * nsv];
            tets.extend(s.tetrahedra.iter().map(|t| t.map(|v| ids[v as usize])));
        }
        // The slab's own adjacency; its ends are left without neighbours there. A face
        // without a neighbour whose corners' classes are those of another such face is a
        // slab end, one of a pair of seam faces (`d` periods apart); the others are real
        // boundary.
        harmonic_types::check_tetrahedra(&s.vertices, &s.tetrahedra)?;
        let nt = s.tetrahedra.len();
        let slab_neighbors = harmonic_types::face_neighbors(&s.tetrahedra)?;
        let face_of = |t: usize, k: usize| harmonic_types::FACES[k].map(|l| s.tetrahedra[t][l]);
        let mut open: HashMap<[u32; 3], (u32, u8)> = HashMap::new();
        // Per slab tetrahedron and face: its seam partner (tetrahedron, face) and the shift
        // `d` in periods from this face's copy to the partner's.
        let mut seam: HashMap<(u32, u8), (u32, u8, [i32; 3])> = HashMap::new();
        for (t, across) in slab_neighbors.iter().enumerate() {
            for (k, &n) in across.iter().enumerate() {
                if n != NO_NEIGHBOR {
                    continue;
                }
                let mut classes = face_of(t, k).map(|v| stuffed.orbit[v as usize]);
                classes.sort_unstable();
                let Some((t2, k2)) = open.remove(&classes) else {
                    open.insert(classes, (t as u32, k as u8));
                    continue;
                };
                // The same class on both faces: the shift between the two copies.
                let v1 = face_of(t, k)[0];
                let o = stuffed.orbit[v1 as usize];
                let v2 = face_of(t2 as usize, k2 as usize)
                    .into_iter()
                    .find(|&v| stuffed.orbit[v as usize] == o)
                    .unwrap_or(v1);
                let (w1, w2) = (stuffed.wrap[v1 as usize], stuffed.wrap[v2 as usize]);
                let d = [0, 1, 2].map(|a| w2[a] - w1[a]);
                seam.insert((t as u32, k as u8), (t2, k2, d));
                seam.insert((t2, k2), (t as u32, k as u8, d.map(|x| -x)));
            }
        }
        // The covering's adjacency, copy by copy: inside a copy the slab's, across a seam
        // the partner's in the copy `d` periods back (none past the covering's ends).
        let copy_index = |sh: [i32; 3]| shifts.iter().position(|x| *x == sh);
        let mut neighbors = Vec::with_capacity(tets.len());
        for sh in &shifts {
            let base = (copy_index(*sh).unwrap_or(0) * nt) as u32;
            for (t, across) in slab_neighbors.iter().enumerate() {
                let mut row = [NO_NEIGHBOR; 4];
                for k in 0..4 {
                    row[k] = if across[k] != NO_NEIGHBOR {
                        base + across[k]
                    } else if let Some(&(t2, _, d)) = seam.get(&(t as u32, k as u8)) {
                        let there = [0, 1, 2].map(|a| sh[a] - d[a]);
                        copy_index(there).map_or(NO_NEIGHBOR, |c| (c * nt) as u32 + t2)
                    } else {
                        NO_NEIGHBOR
                    };
                }
                neighbors.push(row);
            }
        }
        // Tags come from the slab's below.
        let covering =
            TetMesh::with_neighbors(vertices, tets, neighbors, &mut |_, _, _| BoundaryTag::Wall);

        // The slab: its seam faces tagged as such, its real boundary by `tag` (on every core).
        let boundary: Vec<(u32, usize, Point)> = slab_neighbors
            .iter()
            .enumerate()
            .flat_map(|(t, across)| {
                (0..4)
                    .filter(move |&k| across[k] == NO_NEIGHBOR)
                    .map(move |k| (t as u32, k))
            })
            .filter(|&(t, k)| !seam.contains_key(&(t, k as u8)))
            .map(|(t, k)| {
                let f = face_of(t as usize, k);
                let c = Point::from(
                    f.iter()
                        .map(|&v| s.vertices[v as usize].coords)
                        .sum::<Vector>()
                        / 3.0,
                );
                (t, k, c)
            })
            .collect();
        let tags: HashMap<(u32, usize), BoundaryTag> = boundary
            .par_iter()
            .map(|&(t, k, c)| ((t, k), tag(&c)))
            .collect();
        let mut seam_faces = 0;
        let slab = TetMesh::with_neighbors(
            s.vertices.clone(),
            s.tetrahedra.clone(),
            slab_neighbors,
            &mut |t, k, _| match tags.get(&(t, k)) {
                Some(&tag) => tag,
                None => {
                    seam_faces += 1;
                    BoundaryTag::Obstacle(SEAM_PART)
                }
            },
        );
        let mut mesh = PeriodicMesh {
            slab,
            images,
            covering,
            slab_vertex,
            period: stuffed.period,
            copies,
            seam_faces,
        };
        mesh.tag_covering();
        Ok(mesh)
    }

    /// Gives each boundary face of the slab the tag `retag` returns for it (as
    /// [`TetMesh::retag`]) and the covering's faces their slab face's tag.
    pub fn retag(&mut self, retag: &dyn Fn(&[Point; 3], BoundaryTag) -> BoundaryTag) {
        self.slab.retag(retag);
        self.tag_covering();
    }

    /// Every boundary face of the covering gets the tag of the slab face it copies: the same
    /// local face of the same slab tetrahedron (copies are laid out one slab after another).
    /// The covering's outer ends are slab ends and keep the seam's tag.
    fn tag_covering(&mut self) {
        let nt = self.slab.tetrahedra().len();
        for i in 0..self.covering.boundary_faces().len() {
            let f = self.covering.boundary_faces()[i];
            let t = f.tet as usize % nt;
            let tag = self
                .slab
                .boundary_face(t as u32, f.local_face as usize)
                .map_or(BoundaryTag::Obstacle(SEAM_PART), |b| b.tag);
            self.covering.set_tag(i, tag);
        }
    }
}
