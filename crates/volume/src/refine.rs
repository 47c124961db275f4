//! Local refinement of a conforming tetrahedral mesh by longest-edge bisection (Rivara's
//! algorithm), which is how a mesh stuffed at one spacing is graded down to goal regions
//! smaller than that spacing.
//!
//! A tetrahedron is refined by bisecting its longest edge: a new vertex at the edge's middle,
//! and every tetrahedron around the edge cut in two through it, so the mesh stays conforming.
//! Before that, a tetrahedron around the edge whose own longest edge is another one is
//! bisected first (the longest-edge propagation path, followed on a stack). Edges are
//! compared by length, then by a rank of their midpoint the caller gives (the distance to
//! where refinement is wanted), then by their vertex numbers: a strict total order, so the
//! path climbs strictly and ends, and where lengths tie (a lattice has many equal edges) it
//! climbs towards the refined region instead of wandering across the lattice. Children keep their parent's orientation (a vertex replaced by
//! a point on the segment towards the other keeps the sign of the volume), and the shapes
//! stay within a few similarity classes of the parents' (Rivara & Levin 1992; for the
//! body-centred cubic lattice's tetrahedron three bisections give the lattice at half the
//! spacing), so dihedral angles stay bounded; they are measured anyway ([`crate::quality`]).
//!
//! Vertices the caller marks as frozen (a periodic slab's seam, whose two copies must stay
//! identical) are never on a bisected edge's tetrahedra: a tetrahedron whose propagation
//! path reaches one stays as it is.
//!
//! [`refine_periodic`] refines a mesh of a periodic domain as the quotient it is: every
//! vertex is stored once, at its canonical place in one period, and every tetrahedron
//! carries, per corner, the periods to shift that vertex by to give the tetrahedron its true
//! shape. An edge is then one edge however many periods apart its copies lie, its midpoint
//! one new vertex, and both ends of a period are refined alike: nothing is frozen.
//!
//! ```
//! use harmonic_volume::{Point, refine_where, longest_edge, signed_volume};
//! // One tetrahedron, refined until every edge is shorter than 0.3.
//! let mut v = vec![
//!     Point::new(0.0, 0.0, 0.0),
//!     Point::new(1.0, 0.0, 0.0),
//!     Point::new(0.0, 1.0, 0.0),
//!     Point::new(0.0, 0.0, 1.0),
//! ];
//! let mut t = vec![[0, 1, 2, 3]];
//! let report = refine_where(
//!     &mut v,
//!     &mut t,
//!     &|_| false,
//!     &|p| longest_edge(p) > 0.3,
//!     &|_| 0.0,
//!     1_000_000,
//! );
//! assert!(report.bisections > 0 && !report.budget_reached);
//! let total: f64 = t
//!     .iter()
//!     .map(|k| signed_volume(&v[k[0] as usize], &v[k[1] as usize], &v[k[2] as usize], &v[k[3] as usize]))
//!     .sum();
//! assert!((total - 1.0 / 6.0).abs() < 1e-12);
//! assert!(t.iter().all(|k| longest_edge(&k.map(|i| v[i as usize])) <= 0.3));
//! ```

use crate::solid::{Point, Vector};
use harmonic_types::EDGES;

/// What [`refine_where`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RefineReport {
    /// Edges bisected.
    pub bisections: usize,
    /// Passes over the tetrahedra still asking for refinement.
    pub passes: usize,
    /// Tetrahedra left unrefined because their propagation path met a frozen vertex.
    pub frozen: usize,
    /// Whether refinement stopped at the tetrahedron budget.
    pub budget_reached: bool,
}

/// The longest edge length of a tetrahedron.
pub fn longest_edge(p: &[Point; 4]) -> f64 {
    EDGES
        .iter()
        .map(|&[i, j]| (p[i] - p[j]).norm_squared())
        .fold(0.0, f64::max)
        .sqrt()
}

/// Refines the mesh `(vertices, tets)` (conforming, positively oriented) by longest-edge
/// bisection until no tetrahedron asks for it (`want` on its corners), no further than
/// `max_tets` tetrahedra. New vertices are appended to `vertices` (at edge midpoints);
/// `frozen` vertices are never touched (see the module docs). Among edges of equal length,
/// the one whose midpoint has the smaller `rank` is bisected first: pass a distance to where
/// refinement is wanted (or any constant) to keep propagation local.
pub fn refine_where(
    vertices: &mut Vec<Point>,
    tets: &mut Vec<[u32; 4]>,
    frozen: &dyn Fn(u32) -> bool,
    want: &(dyn Fn(&[Point; 4]) -> bool + Sync),
    rank: &dyn Fn(&Point) -> f64,
    max_tets: usize,
) -> RefineReport {
    let mut wraps = Vec::new();
    let mut r = Refiner {
        vertices,
        tets,
        wraps: &mut wraps,
        period: None,
        around: Vec::new(),
        frozen,
        rank,
        touched: Vec::new(),
        longest_of: Vec::new(),
        buffers: Default::default(),
    };
    refine(&mut r, want, max_tets)
}

/// A mesh of a domain periodic along some axes, stored as its quotient (see the module
/// docs): canonical vertices in the period that starts at `origin`, and per tetrahedron the
/// offsets, in periods, that give each corner its place.
#[derive(Clone, Debug, Default)]
pub struct PeriodicTets {
    /// Vertices, each at its canonical place.
    pub vertices: Vec<Point>,
    /// Tetrahedra (positively oriented with their corners shifted).
    pub tets: Vec<[u32; 4]>,
    /// Per tetrahedron and corner: the periods that corner is shifted by.
    pub wraps: Vec<[[i32; 3]; 4]>,
    /// The period along each axis (`None`: not periodic).
    pub period: [Option<f64>; 3],
    /// The lower corner of the canonical period.
    pub origin: Point,
}

impl PeriodicTets {
    /// The shift of `w` periods.
    pub fn offset(&self, w: [i32; 3]) -> Vector {
        offset(self.period, w)
    }

    /// A tetrahedron's corners, shifted to give it its true shape.
    pub fn corners(&self, t: usize) -> [Point; 4] {
        corners_of(
            &self.vertices,
            &self.tets,
            &self.wraps,
            Some((self.period, self.origin)),
            t as u32,
        )
    }
}

/// The shift of `w` periods (0 along an axis that is not periodic): the one place a shift
/// in periods becomes a vector.
pub(crate) fn offset(period: [Option<f64>; 3], w: [i32; 3]) -> Vector {
    Vector::new(
        period[0].map_or(0.0, |l| w[0] as f64 * l),
        period[1].map_or(0.0, |l| w[1] as f64 * l),
        period[2].map_or(0.0, |l| w[2] as f64 * l),
    )
}

/// [`refine_where`] on the quotient mesh of a periodic domain (see the module docs): `want`
/// sees each tetrahedron's shifted corners, `rank` canonical points; new vertices are
/// appended at their canonical places. Every period must be longer than twice the longest
/// edge, so that two vertices share at most one edge.
pub fn refine_periodic(
    mesh: &mut PeriodicTets,
    want: &(dyn Fn(&[Point; 4]) -> bool + Sync),
    rank: &dyn Fn(&Point) -> f64,
    max_tets: usize,
) -> RefineReport {
    let mut r = Refiner {
        vertices: &mut mesh.vertices,
        tets: &mut mesh.tets,
        wraps: &mut mesh.wraps,
        period: Some((mesh.period, mesh.origin)),
        around: Vec::new(),
        frozen: &|_| false,
        rank,
        touched: Vec::new(),
        longest_of: Vec::new(),
        buffers: Default::default(),
    };
    refine(&mut r, want, max_tets)
}

fn refine(
    r: &mut Refiner<'_>,
    want: &(dyn Fn(&[Point; 4]) -> bool + Sync),
    max_tets: usize,
) -> RefineReport {
    let mut report = RefineReport::default();
    let corners = |r: &Refiner, t: u32| r.corners(t);
    let mut candidates: Vec<u32> = {
        use rayon::prelude::*;
        let (vertices, tets, wraps, period) = (&*r.vertices, &*r.tets, &*r.wraps, r.period);
        (0..tets.len() as u32)
            .into_par_iter()
            .filter(|&t| want(&corners_of(vertices, tets, wraps, period, t)))
            .collect()
    };
    if candidates.is_empty() {
        return report;
    }
    r.index();
    while !candidates.is_empty() {
        report.passes += 1;
        r.touched.clear();
        for &t in &candidates {
            if r.tets.len() >= max_tets {
                report.budget_reached = true;
                return report;
            }
            if !want(&corners(r, t)) {
                continue;
            }
            match r.bisect_longest(t) {
                Some(n) => report.bisections += n,
                None => report.frozen += 1,
            }
        }
        let mut next = std::mem::take(&mut r.touched);
        next.sort_unstable();
        next.dedup();
        // The tetrahedra this pass made or changed that are wanted, asked on every core.
        candidates = {
            use rayon::prelude::*;
            let (vertices, tets, wraps, period) = (&*r.vertices, &*r.tets, &*r.wraps, r.period);
            next.into_par_iter()
                .filter(|&t| want(&corners_of(vertices, tets, wraps, period, t)))
                .collect()
        };
    }
    report
}

/// An edge's sort key: quantized squared length, midpoint rank, vertex numbers.
type EdgeKey = (u64, f64, u32, u32);

/// Whether `k` comes after `l` in the order of [`Refiner::key`].
fn greater(k: EdgeKey, l: EdgeKey) -> bool {
    if k.0 != l.0 {
        return k.0 > l.0;
    }
    if k.1 != l.1 {
        return k.1 < l.1;
    }
    (k.2, k.3) > (l.2, l.3)
}

struct Refiner<'a> {
    vertices: &'a mut Vec<Point>,
    tets: &'a mut Vec<[u32; 4]>,
    /// Per tetrahedron and corner, its shift in periods; empty for a mesh that is not
    /// periodic.
    wraps: &'a mut Vec<[[i32; 3]; 4]>,
    /// The periods and the canonical period's lower corner, for a periodic mesh.
    period: Option<([Option<f64>; 3], Point)>,
    /// Per vertex, the tetrahedra that have it.
    around: Vec<Vec<u32>>,
    frozen: &'a dyn Fn(u32) -> bool,
    rank: &'a dyn Fn(&Point) -> f64,
    /// Tetrahedra created or changed in this pass.
    touched: Vec<u32>,
    /// Per tetrahedron, its edge to bisect once [`Refiner::longest`] has found it
    /// ([`UNKNOWN_EDGE`] before, and again once the tetrahedron changes): a propagation
    /// path asks every tetrahedron around each edge on it, and a lattice's tied lengths
    /// make each answer rank several midpoints.
    longest_of: Vec<(u32, u32)>,
    /// [`Refiner::bisect_longest`]'s propagation path and edge star, reused.
    buffers: (Vec<u32>, Vec<u32>),
}

/// [`Refiner::longest_of`] for a tetrahedron not looked at since it last changed.
const UNKNOWN_EDGE: (u32, u32) = (u32::MAX, u32::MAX);

impl Refiner<'_> {
    fn index(&mut self) {
        // Counted first, so that each list is allocated once (a lattice vertex is in 24
        // tetrahedra: pushed from empty, its list was reallocated four or five times, a
        // seventh of a configuration space's meshing), with room for a few bisections.
        let mut count = vec![0u32; self.vertices.len()];
        for tet in self.tets.iter() {
            for &v in tet {
                count[v as usize] += 1;
            }
        }
        self.around = count
            .iter()
            .map(|&c| Vec::with_capacity(c as usize + 4))
            .collect();
        for (t, tet) in self.tets.iter().enumerate() {
            for &v in tet {
                self.around[v as usize].push(t as u32);
            }
        }
    }

    /// A tetrahedron's corners, shifted to give it its true shape.
    fn corners(&self, t: u32) -> [Point; 4] {
        corners_of(self.vertices, self.tets, self.wraps, self.period, t)
    }

    /// Edge `(i, j)` of `t` as its vertex pair `(a, b)` with `a < b`, and `b`'s position in
    /// the frame of `a`'s canonical place: the same numbers whichever tetrahedron around the
    /// edge asks (so lengths and midpoints are computed alike on every copy).
    fn edge(&self, t: u32, [i, j]: [usize; 2]) -> ((u32, u32), Point, Point) {
        let tet = self.tets[t as usize];
        let (i, j) = if tet[i] < tet[j] { (i, j) } else { (j, i) };
        let (a, b) = (tet[i], tet[j]);
        let (pa, pb) = (self.vertices[a as usize], self.vertices[b as usize]);
        match self.period {
            None => ((a, b), pa, pb),
            Some((period, _)) => {
                let w = self.wraps[t as usize];
                let rel = [0, 1, 2].map(|k| w[j][k] - w[i][k]);
                ((a, b), pa, pb + offset(period, rel))
            }
        }
    }

    /// A point moved into the canonical period.
    fn canonical(&self, p: Point) -> (Point, [i32; 3]) {
        let Some((period, origin)) = self.period else {
            return (p, [0; 3]);
        };
        let mut q = p;
        let mut w = [0i32; 3];
        for k in 0..3 {
            if let Some(l) = period[k] {
                let n = ((p[k] - origin[k]) / l).floor();
                w[k] = n as i32;
                q[k] = p[k] - n * l;
            }
        }
        (q, w)
    }

    /// The longest edge of `t` in the strict order of [`Refiner::key`]. The rank (a call to
    /// the caller's function) is asked only of the edges tied for the longest.
    fn longest(&mut self, t: u32) -> (u32, u32) {
        if self.longest_of.len() < self.tets.len() {
            self.longest_of.resize(self.tets.len(), UNKNOWN_EDGE);
        }
        if self.longest_of[t as usize] == UNKNOWN_EDGE {
            self.longest_of[t as usize] = self.find_longest(t);
        }
        self.longest_of[t as usize]
    }

    /// The edge [`Refiner::longest`] gives, found.
    fn find_longest(&self, t: u32) -> (u32, u32) {
        let edges = EDGES.map(|e| self.edge(t, e));
        let lens = edges.map(|(_, pa, pb)| length_key(&pa, &pb));
        let top = lens.iter().copied().max().unwrap_or(0);
        let mut tied = edges
            .iter()
            .zip(&lens)
            .filter(|&(_, &l)| l == top)
            .map(|(e, _)| *e);
        let Some(first) = tied.next() else {
            return edges[0].0;
        };
        let mut best: Option<(EdgeKey, (u32, u32))> = None;
        for e in tied {
            let (b, _) = *best.get_or_insert_with(|| (self.key(first), first.0));
            let k = self.key(e);
            if greater(k, b) {
                best = Some((k, e.0));
            }
        }
        best.map_or(first.0, |(_, e)| e)
    }

    /// An edge's place in the order that decides which edge of a tetrahedron is bisected:
    /// its squared length with the last 20 bits of the mantissa dropped (so lengths equal
    /// but for rounding, as in a lattice, tie), then the smaller `rank` of its midpoint,
    /// then its vertex numbers. Ranking ties by the distance to where refinement is wanted
    /// keeps the propagation path local: every step moves towards it, never across a
    /// uniform lattice.
    fn key(&self, ((a, b), pa, pb): ((u32, u32), Point, Point)) -> EdgeKey {
        let (mid, _) = self.canonical(nalgebra::center(&pa, &pb));
        (length_key(&pa, &pb), (self.rank)(&mid), a, b)
    }

    /// The tetrahedra around edge `(a, b)`, into `out`.
    fn tets_around(&self, (a, b): (u32, u32), out: &mut Vec<u32>) {
        out.clear();
        out.extend(
            self.around[a as usize]
                .iter()
                .copied()
                .filter(|&t| self.tets[t as usize].contains(&b)),
        );
    }

    /// Bisects `t`'s longest edge after whatever its propagation path needs; the number of
    /// bisections, or `None` where the path meets a frozen vertex.
    fn bisect_longest(&mut self, t: u32) -> Option<usize> {
        // The path and the edge's tetrahedra in buffers kept from call to call (a carved
        // goal takes tens of thousands of bisections).
        let (mut stack, mut around) = std::mem::take(&mut self.buffers);
        stack.clear();
        stack.push(t);
        let mut done = Some(0);
        while let Some(&u) = stack.last() {
            let e = self.longest(u);
            self.tets_around(e, &mut around);
            if around
                .iter()
                .any(|&w| self.tets[w as usize].iter().any(|&v| (self.frozen)(v)))
            {
                done = None;
                break;
            }
            if let Some(w) = around.iter().copied().find(|&w| self.longest(w) != e) {
                stack.push(w);
                continue;
            }
            self.bisect(u, e, &around);
            done = done.map(|n| n + 1);
            stack.pop();
        }
        self.buffers = (stack, around);
        done
    }

    /// Bisects edge `(a, b)` of `t` and every tetrahedron `around` it.
    fn bisect(&mut self, t: u32, (a, b): (u32, u32), around: &[u32]) {
        let m = self.vertices.len() as u32;
        let (ia, ib) = {
            let tet = self.tets[t as usize];
            let find = |v: u32| tet.iter().position(|&x| x == v).unwrap_or(0);
            (find(a), find(b))
        };
        let (_, pa, pb) = self.edge(t, [ia, ib]);
        // The midpoint in the frame of `a`'s canonical place, moved into the canonical
        // period: `shift` periods from there.
        let (mid, shift) = self.canonical(nalgebra::center(&pa, &pb));
        self.vertices.push(mid);
        self.around.push(Vec::with_capacity(2 * around.len()));
        for &t in around {
            let tet = self.tets[t as usize];
            let first = tet.map(|v| if v == b { m } else { v });
            let second = tet.map(|v| if v == a { m } else { v });
            let n = self.tets.len() as u32;
            self.tets[t as usize] = first;
            self.tets.push(second);
            if let Some(known) = self.longest_of.get_mut(t as usize) {
                *known = UNKNOWN_EDGE;
            }
            if self.period.is_some() {
                // In this tetrahedron's frame the midpoint lies `shift` periods from `a`'s.
                let w = self.wraps[t as usize];
                let wa = w[tet.iter().position(|&x| x == a).unwrap_or(0)];
                let wm = [0, 1, 2].map(|k| wa[k] + shift[k]);
                let put = |x: u32, wrap: [[i32; 3]; 4]| {
                    let mut wrap = wrap;
                    if let Some(i) = tet.iter().position(|&v| v == x) {
                        wrap[i] = wm;
                    }
                    wrap
                };
                self.wraps[t as usize] = put(b, w);
                self.wraps.push(put(a, w));
            }
            let list = &mut self.around[b as usize];
            if let Some(k) = list.iter().position(|&x| x == t) {
                list.swap_remove(k);
            }
            list.push(n);
            for &v in &tet {
                if v != a && v != b {
                    self.around[v as usize].push(n);
                }
            }
            self.around[m as usize].extend([t, n]);
            self.touched.extend([t, n]);
        }
    }
}

/// Tetrahedron `t`'s corners, shifted by their periods when the mesh is periodic.
fn corners_of(
    vertices: &[Point],
    tets: &[[u32; 4]],
    wraps: &[[[i32; 3]; 4]],
    period: Option<([Option<f64>; 3], Point)>,
    t: u32,
) -> [Point; 4] {
    let tet = tets[t as usize];
    match period {
        None => tet.map(|v| vertices[v as usize]),
        Some((period, _)) => {
            let w = wraps[t as usize];
            [0, 1, 2, 3].map(|i| vertices[tet[i] as usize] + offset(period, w[i]))
        }
    }
}

/// The first part of [`Refiner::key`]: the squared length with the last 20 bits of the
/// mantissa dropped.
fn length_key(pa: &Point, pb: &Point) -> u64 {
    (pa - pb).norm_squared().to_bits() >> 20
}
