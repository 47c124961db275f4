//! Triangle's planar straight line graphs (`.poly` files) read as free space.
//!
//! A `.poly` file lists vertices (or none, and then they come from the `.node` file of the
//! same name), segments with optional boundary markers, hole points and optional regional
//! attributes; `#` starts a comment, and indices start at 0 or 1 (whichever the first vertex
//! uses). [`Pslg::parse`] reads one, [`Pslg::free_space`] finds its free space the way
//! Triangle does with `-p`: triangles reachable from the convex hull without crossing a
//! segment are outside, and so is every triangle reachable from a hole point. What is left
//! must be one region: its outer boundary is the workspace, its holes are obstacles, and the
//! segments inside it (with free space on both sides) and the vertices inside it are kept as
//! mesh constraints ([`crate::Domain::with_constraints`]).
//!
//! Unlike Triangle, which meshes whatever survives, the reader refuses a file whose segments
//! do not close the outer boundary (a segment left outside with a vertex that no other
//! segment continues), a hole point in no closed ring, crossing segments, indices out of
//! range and malformed lines, each in one line naming the file and the line.
//!
//! ```
//! use harmonic_mesh::io::poly::Pslg;
//! // A square with a square hole.
//! let text = "\
//! 8 2 0 0
//! 1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 2 1\n7 2 2\n8 1 2
//! 8 0
//! 1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5
//! 1
//! 1 1.5 1.5
//! ";
//! let free = Pslg::parse(text, "square.poly", None)?.free_space()?;
//! assert_eq!(free.workspace.len(), 4);
//! assert_eq!(free.holes.len(), 1);
//! // An outer boundary with a side missing is refused.
//! let open = text.replace("8 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n", "7 0\n1 1 2\n2 2 3\n3 3 4\n");
//! let e = Pslg::parse(&open, "open.poly", None)?.free_space().unwrap_err();
//! assert!(e.to_string().contains("not closed"), "{e}");
//! # Ok::<(), harmonic_mesh::MeshError>(())
//! ```

use std::collections::HashMap;
use std::path::Path;

use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};

use super::{data_lines, err, num, parse_nodes, read};
use crate::{Frame, MeshError, Point};

/// One segment of a `.poly` file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PslgSegment {
    /// Its end vertices (0-based positions in [`Pslg::vertices`]).
    pub ends: [usize; 2],
    /// Its boundary marker (0 when the file gives none).
    pub marker: i64,
    /// The line of the file it is on.
    pub line: usize,
}

/// A hole point or a regional attribute point of a `.poly` file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PslgPoint {
    /// Where it is.
    pub at: Point,
    /// A region's attribute (0 for holes and when not given).
    pub attribute: f64,
    /// A region's largest triangle area (`None` for holes and when not given or negative).
    pub max_area: Option<f64>,
    /// The line of the file it is on.
    pub line: usize,
}

/// A planar straight line graph as Triangle's `.poly` file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Pslg {
    /// The file's name, for error messages.
    pub file: String,
    /// The vertices (from the `.poly`, or from its `.node` file).
    pub vertices: Vec<Point>,
    /// The first vertex number of the file (0 or 1), by which vertices are named in errors.
    pub first_index: usize,
    /// The segments.
    pub segments: Vec<PslgSegment>,
    /// The hole points.
    pub holes: Vec<PslgPoint>,
    /// The regional attribute points (read and checked; the planner does not use them).
    pub regions: Vec<PslgPoint>,
}

/// The free space of a [`Pslg`]: what [`crate::DomainSpec`] and
/// [`crate::Domain::with_constraints`] take.
#[derive(Clone, Debug, PartialEq)]
pub struct PslgFreeSpace {
    /// The outer boundary, counter-clockwise.
    pub workspace: Vec<Point>,
    /// The holes' boundaries (each a simple polygon, clockwise).
    pub holes: Vec<Vec<Point>>,
    /// Segments (or pieces of them, split at vertices on them) with free space on both sides.
    pub constraint_segments: Vec<[Point; 2]>,
    /// Vertices inside free space that no segment uses.
    pub constraint_points: Vec<Point>,
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Faces not yet reached by a flood.
const FREE: u32 = u32::MAX;
/// Faces reached from the convex hull.
const OUTSIDE: u32 = u32::MAX - 1;

fn input_error(file: &str, message: impl Into<String>) -> MeshError {
    MeshError::Input {
        file: file.to_string(),
        message: message.into(),
    }
}

impl Pslg {
    /// Reads `FILE.poly`, and `FILE.node` when the `.poly` lists no vertices.
    pub fn read(path: &Path) -> Result<Pslg, MeshError> {
        let text = read(path)?;
        let name = path.display().to_string();
        let node_path = path.with_extension("node");
        // Only a .poly with no vertices needs its .node file.
        let needs_node = data_lines(&text)
            .next()
            .is_some_and(|(_, f)| f.first() == Some(&"0"));
        let node = if needs_node {
            if !node_path.exists() {
                return Err(input_error(
                    &name,
                    format!(
                        "lists no vertices, and its vertex file {} does not exist",
                        node_path.display()
                    ),
                ));
            }
            Some((read(&node_path)?, node_path.display().to_string()))
        } else {
            None
        };
        Pslg::parse(
            &text,
            &name,
            node.as_ref().map(|(t, n)| (t.as_str(), n.as_str())),
        )
    }

    /// Parses `.poly` text named `file`; `node` is the text and name of the `.node` file,
    /// used when the `.poly` lists no vertices.
    pub fn parse(text: &str, file: &str, node: Option<(&str, &str)>) -> Result<Pslg, MeshError> {
        let mut lines = data_lines(text);
        let (mut vertices, _, mut first_index) = parse_nodes(file, &mut lines)?;
        if vertices.is_empty() {
            let (node_text, node_file) = node.ok_or_else(|| {
                input_error(file, "lists no vertices and no .node file was given")
            })?;
            let (v, _, base) = parse_nodes(node_file, &mut data_lines(node_text))?;
            vertices = v;
            first_index = base;
        }
        let nv = vertices.len();
        let (ln, head) = lines
            .next()
            .ok_or_else(|| err(file, 0, "no segment count line after the vertices"))?;
        let ns: usize = num(file, ln, &head, 0)?;
        let markers = head.len() > 1 && num::<usize>(file, ln, &head, 1)? > 0;
        let mut segments = Vec::with_capacity(ns.min(super::RESERVE_CAP));
        let mut last = ln;
        for k in 0..ns {
            let (ln, f) = lines
                .next()
                .ok_or_else(|| err(file, last, format!("expected {ns} segments, found {k}")))?;
            last = ln;
            let mut ends = [0usize; 2];
            for (j, end) in ends.iter_mut().enumerate() {
                let v: usize = num(file, ln, &f, j + 1)?;
                if v < first_index || v - first_index >= nv {
                    return Err(err(
                        file,
                        ln,
                        format!(
                            "segment {} refers to vertex {v}, which does not exist (vertices {first_index}..{})",
                            f[0],
                            nv + first_index - 1
                        ),
                    ));
                }
                *end = v - first_index;
            }
            let marker = if markers { num(file, ln, &f, 3)? } else { 0 };
            segments.push(PslgSegment {
                ends,
                marker,
                line: ln,
            });
        }
        let holes = points_block(file, &mut lines, last, "hole", false)?;
        let last = holes.last().map_or(last, |h| h.line);
        let regions = points_block(file, &mut lines, last, "region", true)?;
        if let Some((ln, _)) = lines.next() {
            return Err(err(
                file,
                ln,
                "unexpected data after the regional attributes",
            ));
        }
        Ok(Pslg {
            file: file.to_string(),
            vertices,
            first_index,
            segments,
            holes,
            regions,
        })
    }

    /// The number vertex `v` has in the file.
    fn vertex_name(&self, v: usize) -> usize {
        v + self.first_index
    }

    /// Finds free space as Triangle does (see the module documentation) and splits its
    /// boundary into the workspace and the holes.
    pub fn free_space(&self) -> Result<PslgFreeSpace, MeshError> {
        let file = self.file.as_str();
        if self.vertices.len() < 3 || self.segments.len() < 3 {
            return Err(input_error(
                file,
                format!(
                    "{} vertices and {} segments cannot enclose a region",
                    self.vertices.len(),
                    self.segments.len()
                ),
            ));
        }
        // Topology only: in unit coordinates, so any scale suits the triangulator.
        let frame = Frame::of(&self.vertices);
        let mut cdt = Cdt::new();
        let mut handle = Vec::with_capacity(self.vertices.len());
        let mut first_of: HashMap<FixedVertexHandle, usize> = HashMap::new();
        for (i, &p) in self.vertices.iter().enumerate() {
            let u = frame.to_unit(p);
            let h = cdt.insert(Point2::new(u.x, u.y)).map_err(|e| {
                input_error(
                    file,
                    format!("vertex {}: {e:?} coordinate", self.vertex_name(i)),
                )
            })?;
            first_of.entry(h).or_insert(i);
            handle.push(h);
        }
        for (k, s) in self.segments.iter().enumerate() {
            let [a, b] = s.ends.map(|v| handle[v]);
            if a == b {
                return Err(err(
                    file,
                    s.line,
                    format!(
                        "segment {} has both ends at one point",
                        k + self.first_index
                    ),
                ));
            }
            if !cdt.can_add_constraint(a, b) {
                let other = self.segments[..k]
                    .iter()
                    .find(|o| {
                        let [p, q] = o.ends.map(|v| self.vertices[v]);
                        let [r, t] = s.ends.map(|v| self.vertices[v]);
                        crate::geom::segments_intersect(p, q, r, t)
                    })
                    .map_or(String::new(), |o| format!(" (line {})", o.line));
                return Err(err(
                    file,
                    s.line,
                    format!(
                        "segment {} crosses another segment{other}",
                        k + self.first_index
                    ),
                ));
            }
            cdt.add_constraint(a, b);
        }
        let label = self.flood(&cdt, &first_of)?;
        let free =
            |f: Option<FixedFaceHandle<InnerTag>>| f.is_some_and(|f| label[f.index()] == FREE);
        // Boundary edges of free space, free space on their left, as vertex handles.
        let mut leaving: HashMap<FixedVertexHandle, Vec<FixedVertexHandle>> = HashMap::new();
        let mut constraint_segments = Vec::new();
        for e in cdt.directed_edges() {
            let left = free(e.face().as_inner().map(|f| f.fix()));
            let right = free(e.rev().face().as_inner().map(|f| f.fix()));
            let (a, b) = (e.from().fix(), e.to().fix());
            if left && !right {
                leaving.entry(a).or_default().push(b);
            } else if left && right && e.is_constraint_edge() && a.index() < b.index() {
                constraint_segments.push([first_of[&a], first_of[&b]].map(|v| self.vertices[v]));
            }
        }
        let constraint_points = cdt
            .vertices()
            .filter(|v| {
                v.out_edges()
                    .all(|e| !e.is_constraint_edge() && free(e.face().as_inner().map(|f| f.fix())))
            })
            .map(|v| self.vertices[first_of[&v.fix()]])
            .collect();
        let loops = boundary_loops(&cdt, &leaving);
        let (mut outer, mut holes) = (Vec::new(), Vec::new());
        for l in loops {
            let ring: Vec<Point> = l.iter().map(|h| self.vertices[first_of[h]]).collect();
            if crate::geom::signed_area(&ring) > 0.0 {
                outer.push((ring, l[0]));
            } else {
                holes.push(ring);
            }
        }
        if outer.len() != 1 {
            let which = outer.get(1).map_or(String::new(), |(_, v)| {
                format!(
                    " (the second is bounded by vertex {})",
                    self.vertex_name(first_of[v])
                )
            });
            return Err(input_error(
                file,
                format!(
                    "the segments enclose {} separate regions of free space{which}; a plan needs one outer boundary (with holes)",
                    outer.len()
                ),
            ));
        }
        Ok(PslgFreeSpace {
            workspace: outer.swap_remove(0).0,
            holes,
            constraint_segments,
            constraint_points,
        })
    }

    /// Labels every face: [`OUTSIDE`] if reached from the convex hull, the hole's number if
    /// reached from a hole point, [`FREE`] otherwise; errors if the segments do not close
    /// the outer boundary or a hole lies in no closed ring.
    fn flood(
        &self,
        cdt: &Cdt,
        first_of: &HashMap<FixedVertexHandle, usize>,
    ) -> Result<Vec<u32>, MeshError> {
        let file = self.file.as_str();
        let mut label = vec![FREE; cdt.num_all_faces()];
        let spread = |label: &mut Vec<u32>, start: FixedFaceHandle<InnerTag>, mark: u32| {
            let mut count = 0usize;
            let mut stack = vec![start];
            label[start.index()] = mark;
            while let Some(f) = stack.pop() {
                count += 1;
                for e in cdt.face(f).adjacent_edges() {
                    if e.is_constraint_edge() {
                        continue;
                    }
                    if let Some(g) = e.rev().face().as_inner()
                        && label[g.fix().index()] == FREE
                    {
                        label[g.fix().index()] = mark;
                        stack.push(g.fix());
                    }
                }
            }
            count
        };
        for e in cdt.convex_hull() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(f) = e.rev().face().as_inner()
                && label[f.fix().index()] == FREE
            {
                spread(&mut label, f.fix(), OUTSIDE);
            }
        }
        let free_before = cdt
            .inner_faces()
            .filter(|f| label[f.fix().index()] == FREE)
            .count();
        // A segment with the outside on both sides: the outer boundary leaks past it.
        let outside =
            |h: spade::handles::DirectedEdgeHandle<'_, Point2<f64>, (), spade::CdtEdge<()>, ()>| {
                h.face()
                    .as_inner()
                    .is_none_or(|f| label[f.fix().index()] == OUTSIDE)
            };
        let stray = cdt
            .undirected_edges()
            .filter(|e| e.is_constraint_edge())
            .map(|e| e.as_directed())
            .find(|&d| outside(d) && outside(d.rev()));
        if free_before == 0 || stray.is_some() {
            return Err(self.unclosed(
                cdt,
                first_of,
                stray.map(|d| [d.from().fix(), d.to().fix()]),
            ));
        }
        let unit = Frame::of(&self.vertices);
        let mut eaten = vec![0usize; self.holes.len()];
        for (k, h) in self.holes.iter().enumerate() {
            let u = unit.to_unit(h.at);
            let where_ = format!("hole {} at ({}, {})", k + self.first_index, h.at.x, h.at.y);
            let face = match cdt.locate(Point2::new(u.x, u.y)) {
                PositionInTriangulation::OnFace(f) => Some(f),
                PositionInTriangulation::OnEdge(e) => {
                    let e = cdt.directed_edge(e);
                    if e.is_constraint_edge() {
                        return Err(err(file, h.line, format!("{where_} lies on a segment")));
                    }
                    e.face().as_inner().map(|f| f.fix())
                }
                PositionInTriangulation::OnVertex(_) => {
                    return Err(err(file, h.line, format!("{where_} lies on a vertex")));
                }
                _ => None,
            };
            let Some(face) = face.filter(|f| label[f.index()] != OUTSIDE) else {
                return Err(err(
                    file,
                    h.line,
                    format!(
                        "{where_} lies in no closed ring of segments (outside the outer boundary)"
                    ),
                ));
            };
            if label[face.index()] == FREE {
                eaten[k] = spread(&mut label, face, k as u32);
            }
        }
        let free_after = cdt
            .inner_faces()
            .filter(|f| label[f.fix().index()] == FREE)
            .count();
        if free_after == 0 {
            let k = (0..eaten.len()).max_by_key(|&k| eaten[k]).unwrap_or(0);
            let h = &self.holes[k];
            return Err(err(
                file,
                h.line,
                format!(
                    "hole {} at ({}, {}) lies in no closed ring of segments inside the outer boundary, so it removes all of free space",
                    k + self.first_index,
                    h.at.x,
                    h.at.y
                ),
            ));
        }
        Ok(label)
    }

    /// The error for segments that do not close the outer boundary: a vertex that ends an
    /// odd number of segments, next to `stray` (a segment outside free space) if known.
    fn unclosed(
        &self,
        cdt: &Cdt,
        by_handle: &HashMap<FixedVertexHandle, usize>,
        stray: Option<[FixedVertexHandle; 2]>,
    ) -> MeshError {
        let mut degree: HashMap<FixedVertexHandle, usize> = HashMap::new();
        for e in cdt.undirected_edges().filter(|e| e.is_constraint_edge()) {
            for v in e.vertices() {
                *degree.entry(v.fix()).or_default() += 1;
            }
        }
        let odd = |v: &FixedVertexHandle| degree.get(v).is_some_and(|d| d % 2 == 1);
        let end = stray
            .and_then(|[a, b]| [a, b].into_iter().find(odd))
            .or_else(|| {
                let mut odds: Vec<_> = degree.keys().copied().filter(odd).collect();
                odds.sort_by_key(|v| by_handle[v]);
                odds.first().copied()
            });
        let Some(v) = end else {
            return input_error(
                &self.file,
                "the outer boundary is not closed: the segments enclose no region",
            );
        };
        let vi = by_handle[&v];
        let seg = self.segments.iter().enumerate().find(|(_, s)| {
            s.ends
                .iter()
                .any(|&e| self.vertices[e] == self.vertices[vi])
        });
        let which = seg.map_or(String::new(), |(k, s)| {
            format!(" segment {} (line {})", k + self.first_index, s.line)
        });
        let meet = match degree[&v] {
            1 => format!("only{which} ends there"),
            d => format!("{d} segments end there (an odd number), e.g.{which}"),
        };
        input_error(
            &self.file,
            format!(
                "the outer boundary is not closed at vertex {} ({}, {}): {meet}",
                self.vertex_name(vi),
                self.vertices[vi].x,
                self.vertices[vi].y,
            ),
        )
    }
}

/// Reads a count line and that many `NUMBER X Y [ATTRIBUTE [AREA]]` lines; a missing
/// count (end of file) is an empty block.
fn points_block<'a>(
    file: &str,
    lines: &mut impl Iterator<Item = (usize, Vec<&'a str>)>,
    after: usize,
    what: &str,
    region: bool,
) -> Result<Vec<PslgPoint>, MeshError> {
    let Some((ln, head)) = lines.next() else {
        return Ok(Vec::new());
    };
    let n: usize = num(file, ln, &head, 0)?;
    let mut out = Vec::with_capacity(n.min(super::RESERVE_CAP));
    let mut last = ln.max(after);
    for k in 0..n {
        let (ln, f) = lines
            .next()
            .ok_or_else(|| err(file, last, format!("expected {n} {what}s, found {k}")))?;
        last = ln;
        let x: f64 = num(file, ln, &f, 1)?;
        let y: f64 = num(file, ln, &f, 2)?;
        if !x.is_finite() || !y.is_finite() {
            return Err(err(file, ln, format!("{what} has a non-finite coordinate")));
        }
        let (mut attribute, mut max_area) = (0.0, None);
        if region {
            if f.len() > 3 {
                attribute = num(file, ln, &f, 3)?;
            }
            if f.len() > 4 {
                let a: f64 = num(file, ln, &f, 4)?;
                max_area = (a > 0.0 && a.is_finite()).then_some(a);
            }
        }
        out.push(PslgPoint {
            at: Point::new(x, y),
            attribute,
            max_area,
            line: ln,
        });
    }
    Ok(out)
}

/// Chains boundary edges (`leaving[a]` holds every `b` of an edge `a → b` with free space on
/// its left) into loops; where a loop meets itself at a vertex, it turns the sharpest way
/// (the first edge clockwise from the way it came), so every loop is a simple ring.
fn boundary_loops(
    cdt: &Cdt,
    leaving: &HashMap<FixedVertexHandle, Vec<FixedVertexHandle>>,
) -> Vec<Vec<FixedVertexHandle>> {
    let pos = |v: FixedVertexHandle| {
        let p = cdt.vertex(v).position();
        Point::new(p.x, p.y)
    };
    let mut used: HashMap<(FixedVertexHandle, FixedVertexHandle), bool> = leaving
        .iter()
        .flat_map(|(&a, bs)| bs.iter().map(move |&b| ((a, b), false)))
        .collect();
    let mut starts: Vec<(FixedVertexHandle, FixedVertexHandle)> = used.keys().copied().collect();
    starts.sort_by_key(|&(a, b)| (a.index(), b.index()));
    let mut loops = Vec::new();
    for (a0, b0) in starts {
        if used[&(a0, b0)] {
            continue;
        }
        let mut ring = vec![a0];
        let (mut a, mut b) = (a0, b0);
        used.insert((a, b), true);
        while b != a0 {
            ring.push(b);
            let back = pos(a) - pos(b);
            let next = leaving.get(&b).and_then(|ws| {
                ws.iter()
                    .copied()
                    .filter(|&w| !used[&(b, w)])
                    .min_by(|&w1, &w2| {
                        let cw = |w: FixedVertexHandle| {
                            let d = pos(w) - pos(b);
                            let ccw = (back.x * d.y - back.y * d.x).atan2(back.dot(&d));
                            let c = -ccw;
                            if c <= 0.0 {
                                c + std::f64::consts::TAU
                            } else {
                                c
                            }
                        };
                        cw(w1).total_cmp(&cw(w2))
                    })
            });
            let Some(w) = next else { break };
            used.insert((b, w), true);
            (a, b) = (b, w);
        }
        if ring.len() >= 3 {
            loops.push(ring);
        }
    }
    loops
}
