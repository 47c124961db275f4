//! Constrained Delaunay triangulation and Ruppert refinement of a [`Domain`] with spade.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};

use serde::{Deserialize, Serialize};
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::geom::SegmentIndex;
use crate::grading::SizeField;
use crate::halves::{HalfInput, Seam, choose_cuts, split_inputs};
use crate::options::{Bridges, MeshOptions};
use crate::seam_refine::{Bounds, refine_at_seam};
use crate::{BoundaryTag, Domain, Mesh, MeshError, Point, TaggedRing};

/// What happened while meshing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshReport {
    /// False if refinement stopped at its vertex cap before meeting angle and area bounds.
    pub refinement_complete: bool,
    /// `Some((axis, c))` if the mesh was made in two halves glued along `x = c` (axis 0) or
    /// `y = c` (axis 1); see [`MeshOptions::halves_from`].
    #[serde(default)]
    pub seam: Option<(usize, f64)>,
    /// Vertices of the boundary rings handed to the triangulator.
    pub input_vertices: usize,
    /// Steiner vertices added by refinement.
    pub added_vertices: usize,
    /// The area bound used.
    pub max_area: f64,
    /// The angle bound used, in degrees.
    pub min_angle_deg: f64,
    /// The triangle count estimated before meshing (checked against the budget).
    pub estimated_triangles: usize,
    /// Interior edges joining two boundary vertices that were split (see
    /// [`MeshOptions::bridges`]).
    pub bridges_split: usize,
    /// Such edges left after the last round (0 unless features are much narrower than the
    /// target edge length; all of them with [`Bridges::Kept`]).
    pub bridges_remaining: usize,
    /// Of a mesh made in halves: how often a half took the other half's cut vertices and
    /// was refined around them locally, and how often it took spade's full pass instead
    /// (where local refinement met a boundary ring or an encroached boundary edge).
    #[serde(default)]
    pub seam_refinements: SeamRefinements,
}

/// How the halves of a mesh were refined after exchanging cut vertices (see
/// [`MeshReport::seam_refinements`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SeamRefinements {
    /// Refined around the new cut vertices only.
    pub local: usize,
    /// Refined by another pass over the whole half.
    pub full: usize,
}

/// Area of the lattice triangles relative to `max_area` (about the mean triangle area that
/// Delaunay refinement produces at 30°, so triangle counts match with and without prefill).
const LATTICE_AREA_RATIO: f64 = 0.6;

/// Points of a triangular lattice with triangles of area `area`, inside free space and at
/// least one lattice spacing away from its boundary.
fn lattice_points(domain: &Domain, area: f64, n_ring: usize) -> Vec<Point> {
    let s = (4.0 * area / 3f64.sqrt()).sqrt();
    let (lo, hi) = domain.unit_bbox();
    let nx = ((hi.x - lo.x) / s).ceil() as usize + 2;
    let row = s * 3f64.sqrt() / 2.0;
    let ny = ((hi.y - lo.y) / row).ceil() as usize + 2;
    if !s.is_normal() || nx.saturating_mul(ny) > 50_000_000 {
        return Vec::new();
    }
    // Cells of size s (one per lattice column and row band) near the boundary are blocked.
    let mut blocked = vec![false; nx * ny];
    let mut segs: Vec<(Point, Point)> = Vec::with_capacity(n_ring);
    for ring in domain.unit_rings() {
        let n = ring.points.len();
        for k in 0..n {
            segs.push((ring.points[k], ring.points[(k + 1) % n]));
        }
    }
    let cx = |x: f64| ((x - lo.x) / s).floor().clamp(0.0, (nx - 1) as f64) as usize;
    let cy = |y: f64| ((y - lo.y) / row).floor().clamp(0.0, (ny - 1) as f64) as usize;
    for &(a, b) in &segs {
        let pieces = ((b - a).norm() / s).ceil().max(1.0) as usize;
        for i in 0..pieces {
            let p = a + (b - a) * (i as f64 / pieces as f64);
            let q = a + (b - a) * ((i + 1) as f64 / pieces as f64);
            let (x0, x1) = (cx(p.x.min(q.x) - s), cx(p.x.max(q.x) + s));
            let (y0, y1) = (cy(p.y.min(q.y) - s), cy(p.y.max(q.y) + s));
            for y in y0..=y1 {
                blocked[y * nx + x0..=y * nx + x1].fill(true);
            }
        }
    }
    let mut out = Vec::new();
    let mut xs: Vec<f64> = Vec::new();
    for j in 0..ny {
        let y = lo.y + (j as f64 + 0.5) * row;
        xs.clear();
        for &(a, b) in &segs {
            if (a.y > y) != (b.y > y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(f64::total_cmp);
        let shift = if j % 2 == 0 { 0.0 } else { 0.5 * s };
        for pair in xs.chunks_exact(2) {
            let i0 = ((pair[0] - lo.x - shift) / s).ceil().max(0.0) as usize;
            let i1 = ((pair[1] - lo.x - shift) / s).floor();
            if i1 < 0.0 {
                continue;
            }
            for i in i0..=(i1 as usize).min(nx - 1) {
                let x = lo.x + shift + i as f64 * s;
                if !blocked[j * nx + cx(x)] {
                    out.push(Point::new(x, y));
                }
            }
        }
    }
    out
}

/// Rounds of bridge splitting (each followed by refinement if needed).
const BRIDGE_ROUNDS: usize = 8;

fn sort3(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    let mut v = [a, b, c];
    v.sort_by(f64::total_cmp);
    (v[0], v[1], v[2])
}

/// Midpoints of the interior edges of free faces whose two ends lie on the boundary (the
/// constraint edges, less those on the seam of a mesh made in halves: the seam's own edges
/// are interior edges of the glued mesh), except the third edges of ears; each with one end
/// of its edge, where spade's point location starts.
fn boundary_bridges(
    cdt: &Cdt,
    excluded: &[bool],
    seam: Option<&Seam>,
) -> Vec<(Point2<f64>, FixedVertexHandle)> {
    let free = |h: spade::handles::DirectedEdgeHandle<'_, _, _, _, _>| {
        h.face()
            .as_inner()
            .is_some_and(|f| !excluded.get(f.fix().index()).copied().unwrap_or(false))
    };
    // A constraint edge with free space on both sides is an interior constraint, no boundary.
    let boundary = |e: spade::handles::UndirectedEdgeHandle<'_, _, _, _, _>| {
        let d = e.as_directed();
        e.is_constraint_edge()
            && !(free(d) && free(d.rev()))
            && !seam.is_some_and(|s| {
                let [p, q] = e.positions();
                s.holds_edge(p, q)
            })
    };
    let mut on_boundary = vec![false; cdt.num_vertices()];
    for e in cdt.undirected_edges() {
        if boundary(e) {
            for v in e.vertices() {
                on_boundary[v.fix().index()] = true;
            }
        }
    }
    cdt.undirected_edges()
        .filter(|&e| !boundary(e))
        .filter(|e| e.vertices().iter().all(|v| on_boundary[v.fix().index()]))
        .filter(|e| {
            let d = e.as_directed();
            [d, d.rev()].iter().any(|h| {
                h.face()
                    .as_inner()
                    .is_some_and(|f| !excluded[f.fix().index()])
            })
        })
        // The third edge of an ear (a triangle with two boundary edges, at a corner) seals
        // nothing: splitting it would only chase the corner.
        .filter(|e| {
            let d = e.as_directed();
            [d, d.rev()].iter().all(|h| {
                h.face().is_outer()
                    || !(boundary(h.next().as_undirected()) && boundary(h.prev().as_undirected()))
            })
        })
        .map(|e| {
            let [a, b] = e.positions();
            let mid = Point2::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
            (mid, e.vertices()[0].fix())
        })
        .collect()
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Rounds of the grading pass (each inserts centroids, then refines).
const GRADING_ROUNDS: usize = 40;

/// Centroids of the free faces larger than the local area bound at their centroid.
fn too_large(cdt: &Cdt, excluded: &[bool], size: &SizeField) -> Vec<Point2<f64>> {
    cdt.inner_faces()
        .filter(|f| !excluded[f.fix().index()])
        .filter_map(|f| {
            let [a, b, c] = f.positions();
            let area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
            let m = Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
            (area > size.area_at(m)).then(|| Point2::new(m.x, m.y))
        })
        .collect()
}

fn panic_message(e: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = e.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = e.downcast_ref::<String>() {
        s.clone()
    } else {
        "spade panicked".to_string()
    }
}

/// Position of `(x, y)` (each in `0..2^16`) along a Hilbert curve (below 2^32).
fn hilbert(mut x: u32, mut y: u32) -> u32 {
    let mut d: u32 = 0;
    let mut s: u32 = 1 << 15;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += s * s * ((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = 0xffff - x;
                y = 0xffff - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    d
}

/// `items` sorted by key, items with equal keys kept in their order (least significant digit
/// radix sort, two passes of 16 bits).
fn radix_sort_by_key(mut items: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    if items.len() < 1 << 14 {
        // Below this the two passes' 2^16-bucket tables cost more than a comparison sort.
        // The same order: ties keep their input order, which is by the second field.
        debug_assert!(items.windows(2).all(|w| w[0].1 < w[1].1));
        items.sort_unstable();
        return items;
    }
    let mut out = vec![(0u32, 0u32); items.len()];
    for shift in [0, 16] {
        let mut start = vec![0usize; (1 << 16) + 1];
        for &(k, _) in &items {
            start[((k >> shift) & 0xffff) as usize + 1] += 1;
        }
        for i in 0..1 << 16 {
            start[i + 1] += start[i];
        }
        for &item in &items {
            let slot = &mut start[((item.0 >> shift) & 0xffff) as usize];
            out[*slot] = item;
            *slot += 1;
        }
        std::mem::swap(&mut items, &mut out);
    }
    items
}

/// The distinct triangles `tris` (vertex indices below `nv`, smallest first) in
/// lexicographic order: a counting sort on the first vertex, then the few triangles sharing
/// it by their other two.
fn sorted_triangles(tris: &[[u32; 3]], nv: usize) -> Vec<[u32; 3]> {
    let mut start = vec![0usize; nv + 1];
    for t in tris {
        start[t[0] as usize + 1] += 1;
    }
    for i in 0..nv {
        start[i + 1] += start[i];
    }
    let mut out = vec![[0u32; 3]; tris.len()];
    for t in tris {
        let slot = &mut start[t[0] as usize];
        out[*slot] = *t;
        *slot += 1;
    }
    // `start[v]` is now the end of bucket v, and the start of bucket v + 1.
    let mut begin = 0;
    for &end in &start[..nv] {
        out[begin..end].sort_unstable();
        begin = end;
    }
    out
}

/// A triangulated piece of free space (all of it, or one half) and what refinement left.
struct Part {
    cdt: Cdt,
    /// Faces outside free space (indexed by face).
    excluded: Vec<bool>,
    complete: bool,
    bridges_split: usize,
    bridges_remaining: usize,
    /// The most vertices refinement may grow `cdt` to (see [`Refiner::run`]).
    vertex_cap: usize,
    /// Refinements after taking the other half's cut vertices.
    seam_refinements: SeamRefinements,
}

/// Refinement of one piece: angle and area bounds, then the grading pass, then bridge
/// splitting (see [`MeshOptions`]).
#[derive(Clone)]
struct Refiner<'a> {
    params: RefinementParameters<f64>,
    opts: &'a MeshOptions,
    max_area: f64,
    size_field: Option<&'a SizeField>,
    /// Vertices refinement may add to a piece in all ([`Budget::cap`]).
    cap: usize,
    /// The seam of a mesh made in halves: its constraint edges are not boundary.
    seam: Option<&'a Seam>,
    /// With interior constraints: the boundary rings' segments and the largest x, by which
    /// faces are told inside or outside (spade's own outer-face search counts every
    /// constraint edge as a boundary, and an interior one is not).
    inside: Option<(&'a SegmentIndex, f64)>,
}

impl<'a> Refiner<'a> {
    /// The refiner of one piece under `opts` and `budget` (no seam).
    fn new(opts: &'a MeshOptions, budget: &'a Budget) -> Self {
        Refiner {
            params: RefinementParameters::<f64>::new()
                .exclude_outer_faces(true)
                .with_angle_limit(AngleLimit::from_deg(opts.min_angle_deg))
                .with_max_allowed_area(budget.max_area),
            opts,
            max_area: budget.max_area,
            size_field: budget.size_field.as_ref(),
            cap: budget.cap,
            seam: None,
            inside: None,
        }
    }
}

impl Refiner<'_> {
    /// One refinement pass of spade, adding vertices while the piece has fewer than
    /// `vertex_cap`.
    fn spade_refine(
        &self,
        cdt: &mut Cdt,
        vertex_cap: usize,
    ) -> Result<(Vec<bool>, bool), MeshError> {
        let mut params = self
            .params
            .clone()
            .with_max_additional_vertices(vertex_cap.saturating_sub(cdt.num_vertices()));
        if self.inside.is_some() {
            // Every face is refined (outside ones too); which are free is decided below.
            params = params.exclude_outer_faces(false);
        }
        let result = catch_unwind(AssertUnwindSafe(|| cdt.refine(params)))
            .map_err(|e| MeshError::Triangulation(panic_message(e)))?;
        let mut excluded = vec![false; cdt.num_all_faces()];
        if let Some((rings, x_max)) = self.inside {
            for f in cdt.inner_faces() {
                let [a, b, c] = f.positions();
                let m = Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
                excluded[f.fix().index()] = !rings.ray_parity(m, x_max);
            }
        } else {
            for f in &result.excluded_faces {
                excluded[f.index()] = true;
            }
        }
        Ok((excluded, result.refinement_complete))
    }

    /// Inserts `p`, located from the vertex `hint` next to it if there is one (else from the
    /// last vertex spade touched).
    fn insert(
        cdt: &mut Cdt,
        p: Point2<f64>,
        hint: Option<FixedVertexHandle>,
    ) -> Result<FixedVertexHandle, MeshError> {
        catch_unwind(AssertUnwindSafe(|| match hint {
            Some(h) => cdt.insert_with_hint(p, h),
            None => cdt.insert(p),
        }))
        .map_err(|e| MeshError::Triangulation(panic_message(e)))?
        .map_err(spade_error)
    }

    /// Refines `cdt` completely, or until it has `vertex_cap` vertices (a bound on all of
    /// refinement, grading and bridge splitting together, kept by the part for later rounds
    /// on it): the returned part owns it.
    fn run(&self, mut cdt: Cdt, vertex_cap: usize) -> Result<Part, MeshError> {
        let (opts, max_area) = (self.opts, self.max_area);
        let (mut excluded, mut complete) = self.spade_refine(&mut cdt, vertex_cap)?;
        if let Some(size) = self.size_field {
            for round in 0..=GRADING_ROUNDS {
                let centroids = too_large(&cdt, &excluded, size);
                if centroids.is_empty() {
                    break;
                }
                if round == GRADING_ROUNDS
                    || cdt.num_vertices().saturating_add(centroids.len()) > vertex_cap
                {
                    complete = false;
                    break;
                }
                for c in centroids {
                    Self::insert(&mut cdt, c, None)?;
                }
                let (e, c) = self.spade_refine(&mut cdt, vertex_cap)?;
                excluded = e;
                complete &= c;
            }
        }
        let mut bridges_split = 0;
        let mut bridges_remaining = 0;
        if opts.bridges == Bridges::Kept {
            bridges_remaining = boundary_bridges(&cdt, &excluded, self.seam).len();
        } else {
            let min_sin = opts.min_angle_deg.to_radians().sin();
            for round in 0..=BRIDGE_ROUNDS {
                let mids = boundary_bridges(&cdt, &excluded, self.seam);
                if round == BRIDGE_ROUNDS
                    || mids.is_empty()
                    || cdt.num_vertices().saturating_add(mids.len()) > vertex_cap
                {
                    bridges_remaining = mids.len();
                    break;
                }
                bridges_split += mids.len();
                let mut inserted = Vec::with_capacity(mids.len());
                for (m, hint) in mids {
                    inserted.push(Self::insert(&mut cdt, m, Some(hint))?);
                }
                // Insertion only changes faces around the new vertices: refine again (a pass
                // over the whole mesh) only if one of them breaks the angle or area bound.
                let bad = opts.bridges == Bridges::Refined
                    && inserted.iter().any(|&v| {
                        cdt.vertex(v).out_edges().any(|e| {
                            e.face().as_inner().is_some_and(|f| {
                                let [a, b, c] = f.positions();
                                let area =
                                    0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
                                let (la, lb, lc) = (
                                    ((b.x - c.x).powi(2) + (b.y - c.y).powi(2)).sqrt(),
                                    ((c.x - a.x).powi(2) + (c.y - a.y).powi(2)).sqrt(),
                                    ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt(),
                                );
                                // sin of the smallest angle = 2·area / (product of the two longer sides).
                                let (_, mid, hi) = sort3(la, lb, lc);
                                // An obtuse angle opposite a boundary edge breaks the M-matrix property.
                                let obtuse_boundary = f.adjacent_edges().into_iter().any(|e| {
                                    e.is_constraint_edge()
                                        && e.opposite_position().is_some_and(|o| {
                                            let [p, q] = e.positions();
                                            (p.x - o.x) * (q.x - o.x) + (p.y - o.y) * (q.y - o.y)
                                                < 0.0
                                        })
                                });
                                area > max_area
                                    || 2.0 * area < min_sin * mid * hi * (1.0 - 1e-12)
                                    || obtuse_boundary
                            })
                        })
                    });
                if bad {
                    let (e, c) = self.spade_refine(&mut cdt, vertex_cap)?;
                    excluded = e;
                    complete &= c;
                } else {
                    excluded.resize(cdt.num_all_faces(), false);
                    // Every edge an insertion makes (by splitting or flipping) ends at the new
                    // vertex, which is interior: with no refinement after them, no bridge is
                    // left to look for.
                    bridges_remaining = 0;
                    break;
                }
            }
        }
        Ok(Part {
            cdt,
            excluded,
            complete,
            bridges_split,
            bridges_remaining,
            vertex_cap,
            seam_refinements: SeamRefinements::default(),
        })
    }
}

/// spade's refusal of a vertex, in words: meshing works in unit coordinates, so a coordinate
/// outside spade's range means a point far outside the scene (or not a number).
fn spade_error(e: spade::InsertionError) -> MeshError {
    let what = match e {
        spade::InsertionError::TooSmall => "smaller than 1.8e-43 but not zero",
        spade::InsertionError::TooLarge => "larger than 3.7e150",
        spade::InsertionError::NAN => "not a number",
    };
    MeshError::Triangulation(format!(
        "a vertex coordinate, in the scene's unit coordinates (centred, scaled to size 1), is {what}; the triangulator cannot take it"
    ))
}

/// Boundary components (vertices joined by input edges) with more vertices than this are
/// not bulk-loaded but inserted one by one along the ring (see [`load`]). Circles are
/// discretised with at most 4096 vertices, so scenes without detailed polygons take the
/// bulk path only.
const LONG_RING: usize = 4096;

/// Loads the constraint input into a CDT; crossing input segments are an error.
///
/// spade's bulk loader (a circle sweep from the input's centre) is the fastest way in, except
/// when many input vertices lie on the convex hull of the ones swept so far: then its hull
/// bookkeeping grows quadratically (a circle sampled at 200 000 vertices around the scene's
/// centre took 4.3 s, 50 000 took 0.3 s). So components of more than [`LONG_RING`] vertices
/// are inserted afterwards, vertex after vertex in input (ring) order with the previous one
/// as the hint, which is linear (0.94 s at 200 000, 0.13 s at 50 000), and their edges are
/// added as constraints then.
fn load(verts: Vec<Point2<f64>>, edges: Vec<[usize; 2]>) -> Result<Cdt, MeshError> {
    let long = long_components(verts.len(), &edges);
    let mut conflicts = Vec::new();
    let cdt = catch_unwind(AssertUnwindSafe(|| {
        if !long.iter().any(|&l| l) {
            return Cdt::try_bulk_load_cdt(verts, edges, |e| conflicts.push(e));
        }
        // The short components bulk-loaded (renumbered), then the long ones one by one.
        let mut new_index = vec![usize::MAX; verts.len()];
        let mut short_verts = Vec::new();
        for (i, v) in verts.iter().enumerate() {
            if !long[i] {
                new_index[i] = short_verts.len();
                short_verts.push(*v);
            }
        }
        let short_edges = edges
            .iter()
            .filter(|e| !long[e[0]])
            .map(|e| [new_index[e[0]], new_index[e[1]]])
            .collect();
        let mut cdt = Cdt::try_bulk_load_cdt(short_verts, short_edges, |e| conflicts.push(e))?;
        let mut handles = vec![None; verts.len()];
        let mut hint = None;
        for (i, v) in verts.iter().enumerate() {
            if long[i] {
                let h = match hint {
                    Some(h) => cdt.insert_with_hint(*v, h)?,
                    None => cdt.insert(*v)?,
                };
                handles[i] = Some(h);
                hint = Some(h);
            }
        }
        for e in edges.iter().filter(|e| long[e[0]]) {
            if let (Some(a), Some(b)) = (handles[e[0]], handles[e[1]])
                && a != b
                && cdt.try_add_constraint(a, b).is_empty()
            {
                conflicts.push([a.index(), b.index()]);
            }
        }
        Ok(cdt)
    }))
    .map_err(|e| MeshError::Triangulation(panic_message(e)))?
    .map_err(spade_error)?;
    if let Some(&[a, _]) = conflicts.first() {
        let p = cdt
            .vertices()
            .nth(a)
            .map(|v| v.position())
            .unwrap_or(Point2::new(f64::NAN, f64::NAN));
        return Err(MeshError::Triangulation(format!(
            "{} boundary segments cross or overlap, first near ({}, {})",
            conflicts.len(),
            p.x,
            p.y
        )));
    }
    Ok(cdt)
}

/// Per vertex, whether its component in the graph of `edges` has more than [`LONG_RING`]
/// vertices (union–find, near-linear).
fn long_components(n: usize, edges: &[[usize; 2]]) -> Vec<bool> {
    if n <= LONG_RING {
        return vec![false; n];
    }
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for &[a, b] in edges {
        if a < n && b < n {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut size = vec![0usize; n];
    let roots: Vec<usize> = (0..n).map(|v| root(&mut parent, v)).collect();
    for &r in &roots {
        size[r] += 1;
    }
    roots.iter().map(|&r| size[r] > LONG_RING).collect()
}

/// The unit mesh's vertices in the scene's coordinates; an error if its smallest triangle
/// could not be represented there (see [`Frame::check_user_mesh`](crate::Frame::check_user_mesh)).
fn to_user_vertices(
    frame: &crate::Frame,
    vertices: Vec<Point>,
    triangles: &[[u32; 3]],
) -> Result<Vec<Point>, MeshError> {
    if frame.is_identity() {
        return Ok(vertices);
    }
    if !(1e-100..=1e100).contains(&frame.scale) {
        let smallest = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| vertices[v as usize]);
                0.5 * crate::geom::twice_signed_area(a, b, c)
            })
            .fold(f64::INFINITY, f64::min);
        frame.check_user_mesh(smallest.max(0.0).sqrt())?;
    }
    Ok(vertices.into_iter().map(|p| frame.to_user(p)).collect())
}

/// Rounds of exchanging cut vertices between two halves (each followed by refinement).
const CUT_ROUNDS: usize = 8;

/// Meshes `halves` (the constraint inputs of the two sides of `cut`) on rayon's pool and
/// refines them until they have the same vertices on the cut. `None` if they do not settle
/// within [`CUT_ROUNDS`], or if a half spends its share of the vertex budget.
fn mesh_halves(
    halves: [HalfInput; 2],
    refiner: &Refiner<'_>,
    seam: &Seam,
) -> Result<Option<[(Part, FreeFaces); 2]>, MeshError> {
    let cut = seam.cut;
    let [low, high] = halves;
    let first = |h: HalfInput| {
        // Each half may grow by half the budget's vertices.
        let cap = h.vertices.len().saturating_add(refiner.cap / 2);
        refiner.run(load(h.vertices, h.edges)?, cap)
    };
    let (a, b) = beside(|| first(low), || first(high));
    let a = a.map_err(|e| MeshError::Triangulation(panic_message(e)))?;
    let mut parts = [a?, b?];
    if !parts.iter().all(|p| p.complete) {
        // A half spent its half of the budget (a cut close to a small feature can cost more
        // vertices than the whole mesh does): mesh in one piece, under the whole budget.
        return Ok(None);
    }
    if !cut.exact {
        // Points refinement put on this cut need not be exactly on it: glue only halves
        // whose seam is still the pre-split one.
        // (Seam edges are counted from the seam's vertices, each twice.)
        let intact = |part: &Part| {
            let on_seam: Vec<_> = part
                .cdt
                .vertices()
                .filter(|v| seam.holds(v.position()))
                .collect();
            let ends: usize = on_seam
                .iter()
                .map(|v| {
                    v.out_edges()
                        .filter(|e| {
                            let [p, q] = e.positions();
                            e.is_constraint_edge() && seam.holds_edge(p, q)
                        })
                        .count()
                })
                .sum();
            on_seam.len() == seam.points && ends == 2 * seam.pieces
        };
        return Ok(parts
            .iter()
            .all(intact)
            .then(|| with_free_faces(parts, seam)));
    }
    // The positions along the cut of a part's vertices on it, sorted.
    let on_cut = |part: &Part| {
        let mut t: Vec<f64> = part
            .cdt
            .vertices()
            .map(|v| v.position())
            .filter(|&p| seam.holds(p))
            .map(|p| cut.along(p))
            .collect();
        t.sort_by(f64::total_cmp);
        t
    };
    for _ in 0..CUT_ROUNDS {
        let [ta, tb] = [on_cut(&parts[0]), on_cut(&parts[1])];
        let missing = |have: &[f64], other: &[f64]| -> Vec<f64> {
            other
                .iter()
                .copied()
                .filter(|t| have.binary_search_by(|x| x.total_cmp(t)).is_err())
                .collect()
        };
        let (for_a, for_b) = (missing(&ta, &tb), missing(&tb, &ta));
        if for_a.is_empty() && for_b.is_empty() {
            return Ok(parts
                .iter()
                .all(|p| p.complete)
                .then(|| with_free_faces(parts, seam)));
        }
        // Each half takes the other's cut vertices (exactly on its cut edges, so they split
        // them) and refines again.
        let take = |part: Part, add: Vec<f64>| {
            if add.is_empty() {
                return Ok(part);
            }
            let mut cdt = part.cdt;
            let mut inserted = Vec::with_capacity(add.len());
            for t in add {
                inserted.push(Refiner::insert(&mut cdt, cut.point(t), None)?);
            }
            // Around a few new seam vertices local refinement usually does; spade's full
            // pass over the half where it does not.
            let mut excluded = part.excluded;
            let bounds = Bounds::new(refiner.max_area, refiner.opts.min_angle_deg);
            if refine_at_seam(
                &mut cdt,
                &mut excluded,
                &inserted,
                seam,
                bounds,
                part.vertex_cap,
            ) {
                let mut seam_refinements = part.seam_refinements;
                seam_refinements.local += 1;
                return Ok(Part {
                    cdt,
                    excluded,
                    seam_refinements,
                    ..part
                });
            }
            let mut again = refiner.run(cdt, part.vertex_cap)?;
            again.bridges_split += part.bridges_split;
            again.seam_refinements = part.seam_refinements;
            again.seam_refinements.full += 1;
            Ok::<_, MeshError>(again)
        };
        let [pa, pb] = parts;
        let (a, b) = beside(|| take(pa, for_a), || take(pb, for_b));
        let a = a.map_err(|e| MeshError::Triangulation(panic_message(e)))?;
        parts = [a?, b?];
    }
    Ok(None)
}

/// The two halves with their free faces, read on rayon's pool once the halves are final
/// (`free_faces` only reads a part: a panic there is a bug, and it propagates).
fn with_free_faces(parts: [Part; 2], seam: &Seam) -> [(Part, FreeFaces); 2] {
    let [a, b] = parts;
    let (fa, fb) = rayon::join(|| free_faces(&a, Some(seam)), || free_faces(&b, Some(seam)));
    [(a, fa), (b, fb)]
}

/// Runs `a` and `b` as a pair on rayon's pool (one after the other in a pool of one thread,
/// so `threads = 1` means one), returning `a`'s panic, if any, as an error value: a half's
/// triangulation that panics becomes a meshing error, as it did on its own thread.
fn beside<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (std::thread::Result<A>, B) {
    rayon::join(
        || std::panic::catch_unwind(std::panic::AssertUnwindSafe(a)),
        b,
    )
}

impl Domain {
    /// The triangle count [`Domain::mesh`] expects to make with `opts` (from the free area,
    /// the area bound and the boundary's detail; what it checks against
    /// `opts.max_triangles`), without meshing: for choosing a solver before the mesh exists.
    pub fn estimated_triangles(&self, opts: &MeshOptions) -> Result<usize, MeshError> {
        opts.validate()?;
        let opts = &crate::domain::options_to_unit(opts, &self.frame());
        Ok(Budget::of(self, opts)?.estimated)
    }

    /// Triangulates free space: constrained Delaunay triangulation of the tagged rings,
    /// refined to `opts.min_angle_deg` and `opts.max_area`, vertices numbered along a Hilbert
    /// curve (from [`HILBERT_FROM`] vertices; a smaller mesh keeps the triangulation's order).
    /// Errors at once if the estimated triangle count exceeds `opts.max_triangles`.
    ///
    /// Meshes of more than [`MeshOptions::halves_from`] triangles (estimated; without grading
    /// or prefill) are made as two halves (on two threads of rayon's pool), cut along a line
    /// at `0` or `±2^k` that splits free space evenly and glued along it: the same bounds
    /// hold everywhere, and the result does not depend on the number of cores.
    ///
    /// Meshing works in the domain's unit coordinates (see [`Frame`](crate::Frame)); the mesh
    /// and the report are in the scene's.
    pub fn mesh(&self, opts: &MeshOptions) -> Result<(Mesh, MeshReport), MeshError> {
        opts.validate()?;
        let frame = self.frame();
        let opts = &crate::domain::options_to_unit(opts, &frame);
        let budget = Budget::of(self, opts)?;
        let segments = BoundarySegments::of(self);
        let spacing = crate::domain::edge_for_area(LATTICE_AREA_RATIO * budget.max_area);
        let mut refiner = Refiner::new(opts, &budget);
        if !self.unit_constraints().is_empty() {
            refiner.inside = Some((segments.index, self.unit_bbox().1.x));
        }
        let (parts, input_vertices, seam) =
            match self.mesh_in_halves(opts, &budget, spacing, &segments, &refiner)? {
                Some((parts, n, seam)) => (parts.into(), n, Some(seam)),
                None => {
                    let (part, n) = self.mesh_whole(opts, &budget, spacing, &refiner)?;
                    (vec![part], n, None)
                }
            };
        let seam = seam.as_ref();
        let complete = parts.iter().all(|(p, _)| p.complete);
        let bridges_split = parts.iter().map(|(p, _)| p.bridges_split).sum();
        let seam_refinements = SeamRefinements {
            local: parts.iter().map(|(p, _)| p.seam_refinements.local).sum(),
            full: parts.iter().map(|(p, _)| p.seam_refinements.full).sum(),
        };
        let bridges_remaining = parts.iter().map(|(p, _)| p.bridges_remaining).sum();
        let glued = glue(parts, seam)?;
        let (new_id, vertices) = hilbert_numbering(&glued, self.unit_bbox());
        let triangles = renumbered_triangles(&glued.triangles, &new_id, vertices.len());
        let boundary = tagged_boundary(&glued, &new_id, &segments)?;
        let added_vertices = glued.positions.len().saturating_sub(input_vertices);
        if triangles.is_empty() {
            // Free space has positive area (checked by `Domain::new`), so no triangle at all
            // means the boundary rings were inconsistent: say so rather than return nothing.
            return Err(MeshError::Triangulation(
                "no triangle lies in free space (inconsistent boundary rings)".to_string(),
            ));
        }
        let vertices = to_user_vertices(&frame, vertices, &triangles)?;
        let mesh = Mesh::from_parts(vertices, triangles, &boundary)?;
        let offset = [frame.offset.x, frame.offset.y];
        Ok((
            mesh,
            MeshReport {
                refinement_complete: complete,
                seam: seam.map(|s| (s.cut.axis, frame.len_to_user(s.cut.at) + offset[s.cut.axis])),
                bridges_split,
                bridges_remaining,
                seam_refinements,
                input_vertices,
                added_vertices,
                max_area: frame.area_to_user(budget.max_area),
                min_angle_deg: opts.min_angle_deg,
                estimated_triangles: budget.estimated,
            },
        ))
    }

    /// Meshes free space as two halves on two threads of rayon's pool ([`mesh_halves`]) if it
    /// is large enough and neither graded nor prefilled: the most even cut; if refinement moved
    /// points of a cut that cannot exchange them, the best one that can. Returns the two
    /// parts, the number of input vertices and the seam; `None` for one piece.
    fn mesh_in_halves(
        &self,
        opts: &MeshOptions,
        budget: &Budget,
        spacing: f64,
        segments: &BoundarySegments,
        refiner: &Refiner<'_>,
    ) -> Result<Option<Halves>, MeshError> {
        let (_, hi) = self.unit_bbox();
        let cuts = if budget.estimated >= opts.halves_from
            && opts.grading.is_none()
            && !opts.prefill
            && self.unit_constraints().is_empty()
        {
            choose_cuts(self, spacing)
        } else {
            Vec::new()
        };
        let attempts = cuts
            .first()
            .into_iter()
            .chain(cuts.iter().find(|c| c.exact).filter(|_| !cuts[0].exact));
        for &cut in attempts {
            let Some((inputs, s)) =
                split_inputs(self.unit_rings(), cut, spacing, segments.index, hi.x)
            else {
                continue;
            };
            let input_vertices = inputs.iter().map(|h| h.vertices.len()).sum::<usize>();
            let with_seam = Refiner {
                seam: Some(&s),
                ..refiner.clone()
            };
            if let Some(parts) = mesh_halves(inputs, &with_seam, &s)? {
                return Ok(Some((parts, input_vertices, s)));
            }
        }
        Ok(None)
    }

    /// Meshes free space in one piece: the rings' constraint vertices (deduplicated: rings
    /// may touch) and edges, with prefill the boundary pre-split to the lattice `spacing` and
    /// the lattice inside. Returns the part and the number of input vertices.
    fn mesh_whole(
        &self,
        opts: &MeshOptions,
        budget: &Budget,
        spacing: f64,
        refiner: &Refiner<'_>,
    ) -> Result<((Part, FreeFaces), usize), MeshError> {
        let rings = self.unit_rings();
        let n_ring = budget.ring_vertices;
        let mut ids: HashMap<(u64, u64), usize> = HashMap::with_capacity(n_ring);
        let mut verts: Vec<Point2<f64>> = Vec::with_capacity(n_ring);
        let mut edges: Vec<[usize; 2]> = Vec::with_capacity(n_ring);
        for ring in rings {
            let n = ring.points.len();
            let idx: Vec<usize> = ring
                .points
                .iter()
                .map(|p| {
                    *ids.entry((p.x.to_bits(), p.y.to_bits()))
                        .or_insert_with(|| {
                            verts.push(Point2::new(p.x, p.y));
                            verts.len() - 1
                        })
                })
                .collect();
            for k in 0..n {
                let (a, b) = (ring.points[k], ring.points[(k + 1) % n]);
                // With a lattice inside, split long boundary segments to the lattice
                // spacing up front: refinement would otherwise split them one
                // encroachment at a time.
                let pieces = if opts.prefill {
                    ((b - a).norm() / spacing).ceil().clamp(1.0, 1e6) as usize
                } else {
                    1
                };
                let mut prev = idx[k];
                for i in 1..pieces {
                    let p = a + (b - a) * (i as f64 / pieces as f64);
                    verts.push(Point2::new(p.x, p.y));
                    edges.push([prev, verts.len() - 1]);
                    prev = verts.len() - 1;
                }
                edges.push([prev, idx[(k + 1) % n]]);
            }
        }
        let constraints = self.unit_constraints();
        let mut vertex = |p: Point| {
            *ids.entry((p.x.to_bits(), p.y.to_bits()))
                .or_insert_with(|| {
                    verts.push(Point2::new(p.x, p.y));
                    verts.len() - 1
                })
        };
        let mut interior: Vec<[usize; 2]> = Vec::with_capacity(constraints.segments.len());
        for &(a, b) in &constraints.segments {
            interior.push([vertex(a), vertex(b)]);
        }
        for &p in &constraints.points {
            vertex(p);
        }
        edges.extend(interior);
        let input_vertices = verts.len();
        // The lattice keeps clear of the rings only: not with interior constraints.
        if opts.prefill && constraints.is_empty() {
            verts.extend(
                lattice_points(self, LATTICE_AREA_RATIO * budget.max_area, n_ring)
                    .into_iter()
                    .map(|p| Point2::new(p.x, p.y)),
            );
        }
        let cap = input_vertices.saturating_add(budget.cap);
        let part = refiner.run(load(verts, edges)?, cap)?;
        let faces = free_faces(&part, None);
        Ok(((part, faces), input_vertices))
    }
}

/// Free space meshed in two halves: the parts, the number of their input vertices and the
/// seam they are glued along.
type Halves = ([(Part, FreeFaces); 2], usize, Seam);

/// The size of a mesh before it is made: the area bound, the grading's size field, the
/// triangle estimate checked against the budget, and the refinement's vertex cap.
struct Budget {
    /// The area bound used (`max_area`, or free area / 20000).
    max_area: f64,
    size_field: Option<SizeField>,
    /// The estimated triangle count.
    estimated: usize,
    /// The number of vertices of the free-space rings.
    ring_vertices: usize,
    /// Largest number of vertices refinement may add.
    cap: usize,
}

impl Budget {
    /// The budget of meshing `domain` with `opts`; an error if the estimate exceeds
    /// `opts.max_triangles`.
    fn of(domain: &Domain, opts: &MeshOptions) -> Result<Budget, MeshError> {
        let max_area = opts.max_area.unwrap_or(domain.unit_free_area() / 20000.0);
        let n_ring: usize = domain.unit_rings().iter().map(|r| r.points.len()).sum();
        let size_field = opts
            .grading
            .as_ref()
            .map(|g| SizeField::new(domain, max_area, g));
        let detail =
            BoundaryDetail::of(domain.unit_rings(), crate::domain::edge_for_area(max_area));
        // With interior constraints refinement runs over the whole convex hull (see
        // `Refiner::inside`): count what lies outside free space too, bounded by the box.
        let (lo, hi) = domain.unit_bbox();
        let outside = if domain.unit_constraints().is_empty() {
            0.0
        } else {
            ((hi.x - lo.x) * (hi.y - lo.y) - domain.unit_free_area()).max(0.0)
        };
        // Refinement at 30° gives about 1.6 triangles per max_area, plus what short
        // boundary edges force around them.
        let est = 1.6 * (domain.unit_free_area() + outside) / max_area
            + detail.total
            + size_field.as_ref().map_or(0.0, SizeField::extra_triangles);
        let estimated = if est.is_finite() && est < 1e18 {
            est.ceil() as usize
        } else {
            usize::MAX
        };
        if estimated > opts.max_triangles {
            // Boundary detail: the obstacle forcing the most triangles, if its share is what
            // exceeds the budget.
            if let Some((obstacle, vertices, forced)) = detail.worst_obstacle()
                && est - forced <= opts.max_triangles as f64
            {
                // Chords of length h on a curve of radius ~ρ deviate by h²/(8ρ); a tenth
                // of the target edge keeps well within that for any ρ above h.
                let h = crate::domain::edge_for_area(max_area);
                return Err(MeshError::TooDetailed {
                    obstacle: obstacle as usize,
                    vertices,
                    estimated,
                    limit: opts.max_triangles,
                    suggest: domain.frame().len_to_user(0.1 * h),
                });
            }
            return Err(MeshError::TooManyTriangles {
                estimated,
                limit: opts.max_triangles,
            });
        }
        let cap = (opts.max_triangles / 2 + 1).min(
            estimated
                .saturating_mul(2)
                .max(crate::options::MIN_VERTEX_BUDGET),
        );
        Ok(Budget {
            max_area,
            size_field,
            estimated,
            ring_vertices: n_ring,
            cap,
        })
    }
}

/// Triangles that Ruppert refinement at 30° makes around a boundary edge much shorter than
/// the target edge length, on top of the area-driven ones: the mesh must start at the edge's
/// size and grows geometrically away from it, and the layers sum to about this many
/// triangles per edge. Measured: 8.7 (a circle sampled at 50 000 vertices) and 8.75 (200 000)
/// triangles per edge at a target edge 840 and 3 400 times the edge length.
const TRIANGLES_PER_SHORT_EDGE: f64 = 9.0;

/// What the boundary's detail costs: the triangles short boundary edges force, in all and
/// per obstacle. One pass over the ring edges.
struct BoundaryDetail {
    /// Triangles forced by all short edges.
    total: f64,
    /// Per obstacle (by input index): its ring vertices and the triangles its edges force.
    per_obstacle: HashMap<u32, (usize, f64)>,
}

impl BoundaryDetail {
    /// The detail of `rings` meshed at the target edge length `h`: an edge of length
    /// `e < h` forces about [`TRIANGLES_PER_SHORT_EDGE`] × (1 − e/h)² triangles (none at
    /// `e ≥ h`, whose splitting the area term counts). The square fits the forests' edges
    /// of 0.1–0.4 h (1.08–1.15 × what is made; 1.23–1.38 × with the linear law).
    fn of(rings: &[TaggedRing], h: f64) -> BoundaryDetail {
        let mut total = 0.0;
        let mut per_obstacle: HashMap<u32, (usize, f64)> = HashMap::new();
        for ring in rings {
            let n = ring.points.len();
            for k in 0..n {
                let e = (ring.points[(k + 1) % n] - ring.points[k]).norm();
                let forced = if e < h {
                    TRIANGLES_PER_SHORT_EDGE * (1.0 - e / h).powi(2)
                } else {
                    0.0
                };
                total += forced;
                if let BoundaryTag::Obstacle(i) = ring.tags[k] {
                    let entry = per_obstacle.entry(i).or_default();
                    entry.0 += 1;
                    entry.1 += forced;
                }
            }
        }
        BoundaryDetail {
            total,
            per_obstacle,
        }
    }

    /// The obstacle whose edges force the most triangles: its index, ring vertices and
    /// forced triangles (the lowest index among equals).
    fn worst_obstacle(&self) -> Option<(u32, usize, f64)> {
        self.per_obstacle
            .iter()
            .map(|(&i, &(v, f))| (i, v, f))
            .max_by(|a, b| a.2.total_cmp(&b.2).then(b.0.cmp(&a.0)))
    }
}

/// Every boundary segment of free space with its tag, and an index of them (by position in
/// `tags`) to tag the mesh's boundary edges.
struct BoundarySegments<'a> {
    tags: Vec<(Point, Point, BoundaryTag)>,
    index: &'a SegmentIndex,
    /// The segments by their first end (its bits; free space on the left), sorted: a mesh
    /// boundary edge leaving a ring vertex lies on a segment leaving it.
    by_start: Vec<([u64; 2], u32)>,
}

impl<'a> BoundarySegments<'a> {
    /// The segments of `domain`'s unit rings, with the domain's own index of them.
    fn of(domain: &'a Domain) -> BoundarySegments<'a> {
        let tags: Vec<(Point, Point, BoundaryTag)> = domain
            .unit_rings()
            .iter()
            .flat_map(|ring| {
                let n = ring.points.len();
                (0..n).map(move |k| (ring.points[k], ring.points[(k + 1) % n], ring.tags[k]))
            })
            .collect();
        let mut by_start: Vec<([u64; 2], u32)> = tags
            .iter()
            .enumerate()
            .map(|(k, (a, _, _))| (point_key(*a), k as u32))
            .collect();
        by_start.sort_unstable();
        BoundarySegments {
            tags,
            index: domain.unit_boundary_index(),
            by_start,
        }
    }

    /// The segments leaving the ring vertex at `a` (none if `a` is not a ring vertex).
    fn leaving(&self, a: Point) -> &[([u64; 2], u32)] {
        let key = point_key(a);
        let from = self.by_start.partition_point(|e| e.0 < key);
        let to = from + self.by_start[from..].partition_point(|e| e.0 == key);
        &self.by_start[from..to]
    }

    /// The segment the mesh boundary edge `a -> b` lies on, if `a` is a ring vertex: the one
    /// leaving `a` that `b` lies on (up to rounding; unit coordinates, sides of about 10).
    fn leaving_through(&self, a: Point, b: Point) -> Option<u32> {
        self.leaving(a).iter().map(|e| e.1).find(|&k| {
            let (p, q, _) = self.tags[k as usize];
            q == b || crate::geom::point_segment_distance(b, p, q) <= ON_SEGMENT
        })
    }

    /// The segment nearest the midpoint of `a -> b` (a piece of a split segment).
    fn nearest(&self, a: Point, b: Point) -> Result<u32, MeshError> {
        let m = Point::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
        let (_, k) = self.index.nearest_near(m, ON_SEGMENT).ok_or_else(|| {
            MeshError::Triangulation("free space has no boundary segments".to_string())
        })?;
        Ok(k)
    }
}

/// How far a point refinement put on a ring segment may lie from it (rounding; unit
/// coordinates, sides of about 10).
const ON_SEGMENT: f64 = 1e-9;

/// The key of a point in [`BoundarySegments::by_start`].
fn point_key(p: Point) -> [u64; 2] {
    [p.x.to_bits(), p.y.to_bits()]
}

/// The parts of a mesh under one numbering of their vertices.
struct Glued {
    /// Every vertex of every part (a vertex on the seam once).
    positions: Vec<Point>,
    /// The free triangles, counter-clockwise.
    triangles: Vec<[usize; 3]>,
    /// The boundary edges `(from, to)`, free space on their left.
    boundary: Vec<(usize, usize)>,
}

/// One numbering of the parts' vertices: the first part's as they are, then the others', a
/// vertex on the seam being the first part's.
fn glue(parts: Vec<(Part, FreeFaces)>, seam: Option<&Seam>) -> Result<Glued, MeshError> {
    let mut positions: Vec<Point> = Vec::new();
    let mut on_seam: HashMap<u64, usize> = HashMap::new();
    let mut tri_raw: Vec<[usize; 3]> = Vec::new();
    let mut bnd_raw: Vec<(usize, usize)> = Vec::new();
    for (k, (part, (tris, bnd))) in parts.into_iter().enumerate() {
        let mut ids = Vec::with_capacity(part.cdt.num_vertices());
        for v in part.cdt.vertices() {
            let p = v.position();
            let key = seam
                .filter(|s| s.holds(p))
                .map(|s| s.cut.along(p).to_bits());
            let id = match (key, k) {
                (Some(key), 0) => {
                    on_seam.insert(key, positions.len());
                    positions.len()
                }
                (Some(key), _) => *on_seam.get(&key).ok_or_else(|| {
                    MeshError::Triangulation("the two halves disagree on the seam".to_string())
                })?,
                (None, _) => positions.len(),
            };
            if id == positions.len() {
                positions.push(Point::new(p.x, p.y));
            }
            ids.push(id);
        }
        if k == 0 {
            // Numbered as they are.
            tri_raw = tris;
            bnd_raw = bnd;
        } else {
            tri_raw.extend(tris.iter().map(|t| t.map(|v| ids[v])));
            bnd_raw.extend(bnd.iter().map(|&(a, b)| (ids[a], ids[b])));
        }
    }
    Ok(Glued {
        positions,
        triangles: tri_raw,
        boundary: bnd_raw,
    })
}

/// Vertices from which a mesh is numbered along a Hilbert curve. The numbering costs ~600
/// instructions a vertex: on Nav2's tb3_sandbox map (317 vertices) a twentieth of the first
/// plan, where the triangulation's own order factors as fast. `harmonic_fem` factors small
/// systems in their own numbering (`NATURAL_ORDER_BELOW`) and relies on its locality: on
/// depot (1 100 vertices) the triangulation's order doubled the solve (0.5 → 1.0–1.3 ms).
pub const HILBERT_FROM: usize = 512;

/// The used vertices renumbered along a Hilbert curve over the bounding box `(lo, hi)` (kept in
/// their order below [`HILBERT_FROM`] vertices): per glued vertex its new number (`u32::MAX`
/// if unused), and the vertices in new order.
fn hilbert_numbering(glued: &Glued, (lo, hi): (Point, Point)) -> (Vec<u32>, Vec<Point>) {
    let positions = &glued.positions;
    let mut used = vec![false; positions.len()];
    for t in &glued.triangles {
        for &v in t {
            used[v] = true;
        }
    }
    let used_ids = (0..positions.len()).filter(|&v| used[v]);
    let order: Vec<u32> = if positions.len() < HILBERT_FROM {
        // Small enough for the caches in any order: the triangulation's own.
        used_ids.map(|v| v as u32).collect()
    } else {
        let span = (hi.x - lo.x).max(hi.y - lo.y).max(f64::MIN_POSITIVE);
        let q = |c: f64, l: f64| (((c - l) / span).clamp(0.0, 1.0) * 65535.0) as u32;
        let keyed = used_ids
            .map(|v| {
                let p = positions[v];
                (hilbert(q(p.x, lo.x), q(p.y, lo.y)), v as u32)
            })
            .collect();
        radix_sort_by_key(keyed)
            .into_iter()
            .map(|(_, v)| v)
            .collect()
    };
    let mut new_id = vec![u32::MAX; positions.len()];
    let mut vertices = Vec::with_capacity(order.len());
    for (i, &v) in order.iter().enumerate() {
        new_id[v as usize] = i as u32;
        vertices.push(positions[v as usize]);
    }
    (new_id, vertices)
}

/// The triangles in the new numbers, rotated so the smallest comes first (keeps
/// orientation; large meshes on two threads of rayon's pool) and sorted.
fn renumbered_triangles(tri_raw: &[[usize; 3]], new_id: &[u32], nv: usize) -> Vec<[u32; 3]> {
    let renumber = |tris: &[[usize; 3]], out: &mut [[u32; 3]]| {
        for (t, o) in tris.iter().zip(out.iter_mut()) {
            let t = t.map(|v| new_id[v]);
            let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
            *o = [t[k], t[(k + 1) % 3], t[(k + 2) % 3]];
        }
    };
    let mut rotated = vec![[0u32; 3]; tri_raw.len()];
    harmonic_types::map_in_two(tri_raw, &mut rotated, renumber);
    sorted_triangles(&rotated, nv)
}

/// The boundary edges in the new numbers, each with the tag of the ring segment it lies on.
///
/// An edge leaving a ring vertex lies on the segment leaving that vertex through its other
/// end; an edge leaving a point refinement put on a segment lies on the segment of the edge
/// coming into that point, so walking back along the boundary to an edge leaving a ring
/// vertex finds it. Where the walk is not clear (a vertex with several incoming edges) the
/// segment nearest the edge's midpoint is taken.
fn tagged_boundary(
    glued: &Glued,
    new_id: &[u32],
    segments: &BoundarySegments,
) -> Result<Vec<(u32, u32, BoundaryTag)>, MeshError> {
    const NONE: u32 = u32::MAX;
    const SEVERAL: u32 = u32::MAX - 1;
    let positions = &glued.positions;
    let edges = &glued.boundary;
    let mut incoming = vec![NONE; positions.len()];
    let mut segment: Vec<u32> = Vec::with_capacity(edges.len());
    for (i, &(a, b)) in edges.iter().enumerate() {
        incoming[b] = if incoming[b] == NONE {
            i as u32
        } else {
            SEVERAL
        };
        segment.push(
            segments
                .leaving_through(positions[a], positions[b])
                .unwrap_or(NONE),
        );
    }
    let mut walked: Vec<usize> = Vec::new();
    for i in 0..edges.len() {
        if segment[i] != NONE {
            continue;
        }
        // Back along the boundary through points on a segment, at most once round a ring;
        // every edge walked over lies on the segment found.
        walked.clear();
        walked.push(i);
        let mut found = NONE;
        for _ in 0..edges.len() {
            let a = edges[walked[walked.len() - 1]].0;
            let k = incoming[a];
            if k >= SEVERAL || !segments.leaving(positions[a]).is_empty() {
                break;
            }
            if segment[k as usize] != NONE {
                found = segment[k as usize];
                break;
            }
            walked.push(k as usize);
        }
        if found == NONE {
            let (a, b) = edges[i];
            segment[i] = segments.nearest(positions[a], positions[b])?;
        } else {
            for &j in &walked {
                segment[j] = found;
            }
        }
    }
    Ok(edges
        .iter()
        .zip(&segment)
        .map(|(&(a, b), &k)| (new_id[a], new_id[b], segments.tags[k as usize].2))
        .collect())
}

/// Triangles (vertex numbers) and boundary edges `(from, to)` of a part.
type FreeFaces = (Vec<[usize; 3]>, Vec<(usize, usize)>);

/// The free faces of `part` as triangles of its vertex numbers (counter-clockwise) and its boundary edges
/// (free space on their left), leaving out edges on the seam; from one pass over the edge array
/// (both half-edges of an undirected edge are stored together, so this reads memory in order
/// instead of jumping from each face to its edges and their twins).
fn free_faces(part: &Part, seam: Option<&Seam>) -> FreeFaces {
    let cdt = &part.cdt;
    let excluded = &part.excluded;
    // Face `f` collects its three directed edges `from -> to` (local vertex indices).
    let mut face_edges = vec![[u32::MAX; 6]; cdt.num_all_faces()];
    let mut bnd_raw: Vec<(usize, usize)> = Vec::new();
    let free = |f: Option<usize>| f.filter(|&i| !excluded.get(i).copied().unwrap_or(true));
    for e in cdt.undirected_edges() {
        let d = e.as_directed();
        let (a, b) = (d.from().fix().index() as u32, d.to().fix().index() as u32);
        let left = free(d.face().as_inner().map(|f| f.fix().index()));
        let right = free(d.rev().face().as_inner().map(|f| f.fix().index()));
        let on_cut = seam.is_some_and(|s| {
            let [p, q] = e.positions();
            s.holds_edge(p, q)
        });
        for (face, from, to, other) in [(left, a, b, right), (right, b, a, left)] {
            if let Some(f) = face {
                let slots = &mut face_edges[f];
                let k = slots.iter().step_by(2).position(|&x| x == u32::MAX);
                let k = 2 * k.expect("a face has three edges");
                slots[k] = from;
                slots[k + 1] = to;
                if other.is_none() && !on_cut {
                    bnd_raw.push((from as usize, to as usize));
                }
            }
        }
    }
    // Each free face as its vertices counter-clockwise: a -> b, then the edge leaving b.
    let tri_raw = face_edges
        .iter()
        .filter(|s| s[0] != u32::MAX)
        .map(|s| {
            let c = if s[2] == s[1] { s[3] } else { s[5] };
            [s[0], s[1], c].map(|v| v as usize)
        })
        .collect();
    (tri_raw, bnd_raw)
}

#[cfg(test)]
mod tests {
    use super::{hilbert, radix_sort_by_key, sorted_triangles};

    #[test]
    fn radix_sort_is_a_stable_sort_by_key() {
        let mut x: u32 = 12345;
        // Below and above the size where the radix passes take over.
        for n in [5000, 40_000] {
            let items: Vec<(u32, u32)> = (0..n)
                .map(|i| {
                    x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                    // Few distinct low digits and high digits, so ties are common.
                    (x & 0x000f_000f, i)
                })
                .collect();
            let mut expected = items.clone();
            expected.sort_unstable();
            assert_eq!(radix_sort_by_key(items), expected, "{n} items");
        }
    }

    #[test]
    fn triangles_come_out_in_lexicographic_order() {
        let tris = vec![[2, 5, 3], [0, 4, 1], [2, 3, 4], [0, 1, 2], [1, 3, 2]];
        let mut expected = tris.clone();
        expected.sort_unstable();
        assert_eq!(sorted_triangles(&tris, 6), expected);
    }

    #[test]
    fn hilbert_is_a_bijection_on_a_small_grid() {
        let mut seen = std::collections::HashSet::new();
        for x in 0..64 {
            for y in 0..64 {
                assert!(seen.insert(hilbert(x << 10, y << 10)));
            }
        }
        // Consecutive cells along the curve are grid neighbours at the finest level.
        let mut cells: Vec<(u32, (i64, i64))> = (0..256u32)
            .flat_map(|x| (0..256u32).map(move |y| (x, y)))
            .map(|(x, y)| (hilbert(x, y), (x as i64, y as i64)))
            .collect();
        cells.sort_unstable();
        for w in cells.windows(2) {
            let (a, b) = (w[0].1, w[1].1);
            assert_eq!((a.0 - b.0).abs() + (a.1 - b.1).abs(), 1, "{a:?} {b:?}");
        }
    }
}
