//! Reading and writing Shewchuk's Triangle formats (`.node`, `.ele`, `.poly`), so meshes can
//! travel to and from Triangle, FreeFEM and other tools.
//!
//! Boundary markers carry the [`BoundaryTag`]s:
//!
//! | marker | meaning |
//! |---|---|
//! | 0 | interior (no tag) |
//! | 1 | [`BoundaryTag::Wall`] |
//! | 100 + i | [`BoundaryTag::Obstacle`]`(i)`, for `i < 999 900` |
//! | 1 000 000 + j | [`BoundaryTag::Goal`]`(j)` |
//!
//! Vertex markers in `.node` are the vertex tags ([`Mesh::vertex_tags`]); segment markers in
//! `.poly` are the edge tags. Written files number from 0 (Triangle accepts 0- or 1-based
//! files; the readers detect which from the first index).
//!
//! ```
//! use harmonic_mesh::{BoundaryTag, Mesh, Point, io};
//! let m = Mesh::from_parts(
//!     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)],
//!     vec![[0, 1, 2]],
//!     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Goal(0)), (2, 0, BoundaryTag::Obstacle(3))],
//! )?;
//! let back = io::from_triangle(&io::to_node(&m)?, &io::to_ele(&m), Some(&io::to_poly(&m)?))?;
//! assert_eq!(back.vertices(), m.vertices());
//! assert_eq!(back.boundary_edges(), m.boundary_edges());
//! # Ok::<(), harmonic_mesh::MeshError>(())
//! ```

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::{BoundaryTag, Mesh, MeshError, Point};

pub mod imported;
pub mod msh;
pub mod poly;

pub use imported::ImportedMesh;

const OBSTACLE_BASE: i64 = 100;
const GOAL_BASE: i64 = 1_000_000;

/// The Triangle boundary marker of a tag (see the module documentation).
pub fn marker_of(tag: BoundaryTag) -> Result<i64, MeshError> {
    match tag {
        BoundaryTag::Wall => Ok(1),
        BoundaryTag::Obstacle(i) if i64::from(i) < GOAL_BASE - OBSTACLE_BASE => {
            Ok(OBSTACLE_BASE + i64::from(i))
        }
        BoundaryTag::Obstacle(i) => Err(MeshError::Io {
            file: "marker".to_string(),
            line: 0,
            message: format!("obstacle index {i} is too large for a boundary marker"),
        }),
        BoundaryTag::Goal(j) => Ok(GOAL_BASE + i64::from(j)),
    }
}

/// The tag of a Triangle boundary marker; `None` for 0 (interior) and unknown markers.
pub fn tag_of_marker(m: i64) -> Option<BoundaryTag> {
    match m {
        1 => Some(BoundaryTag::Wall),
        m if (OBSTACLE_BASE..GOAL_BASE).contains(&m) => {
            Some(BoundaryTag::Obstacle((m - OBSTACLE_BASE) as u32))
        }
        m if m >= GOAL_BASE && m - GOAL_BASE <= i64::from(u32::MAX) => {
            Some(BoundaryTag::Goal((m - GOAL_BASE) as u32))
        }
        _ => None,
    }
}

/// The `.node` file of the mesh: all vertices with their boundary markers.
pub fn to_node(mesh: &Mesh) -> Result<String, MeshError> {
    let mut s = String::new();
    let _ = writeln!(s, "{} 2 0 1", mesh.vertices().len());
    for (i, (p, tag)) in mesh.vertices().iter().zip(mesh.vertex_tags()).enumerate() {
        let m = match tag {
            Some(t) => marker_of(*t)?,
            None => 0,
        };
        let _ = writeln!(s, "{i} {:?} {:?} {m}", p.x, p.y);
    }
    Ok(s)
}

/// The `.ele` file of the mesh: counter-clockwise triangles.
pub fn to_ele(mesh: &Mesh) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{} 3 0", mesh.triangles().len());
    for (i, t) in mesh.triangles().iter().enumerate() {
        let _ = writeln!(s, "{i} {} {} {}", t[0], t[1], t[2]);
    }
    s
}

/// A `.poly` file describing the mesh's boundary (vertices are taken from the `.node` file): its boundary edges as
/// marked segments, and one hole point per boundary loop (just outside free space, beside the
/// loop's longest edge), so Triangle can re-mesh the same domain.
pub fn to_poly(mesh: &Mesh) -> Result<String, MeshError> {
    let edges = mesh.boundary_edges();
    let mut s = String::new();
    // No vertices here: Triangle then reads them from the .node file of the same name.
    let _ = writeln!(s, "0 2 0 1");
    let _ = writeln!(s, "{} 1", edges.len());
    for (i, e) in edges.iter().enumerate() {
        let _ = writeln!(
            s,
            "{i} {} {} {}",
            e.vertices[0],
            e.vertices[1],
            marker_of(e.tag)?
        );
    }
    // One hole point per loop: to the right of the longest edge of the loop.
    let mut by_start: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        by_start.entry(e.vertices[0]).or_default().push(i);
    }
    let mut seen = vec![false; edges.len()];
    let mut holes: Vec<Point> = Vec::new();
    for start in 0..edges.len() {
        if seen[start] {
            continue;
        }
        let mut best = (0.0, start);
        let mut e = start;
        while !seen[e] {
            seen[e] = true;
            let [a, b] = edges[e].vertices.map(|v| mesh.vertices()[v as usize]);
            let len = (b - a).norm();
            if len > best.0 {
                best = (len, e);
            }
            let Some(next) = by_start
                .get(&edges[e].vertices[1])
                .and_then(|l| l.iter().copied().find(|&x| !seen[x]))
            else {
                break;
            };
            e = next;
        }
        let [a, b] = edges[best.1].vertices.map(|v| mesh.vertices()[v as usize]);
        let d = b - a;
        let m = a + d * 0.5;
        holes.push(Point::new(m.x + d.y * 1e-6, m.y - d.x * 1e-6));
    }
    let _ = writeln!(s, "{}", holes.len());
    for (i, h) in holes.iter().enumerate() {
        let _ = writeln!(s, "{i} {:?} {:?}", h.x, h.y);
    }
    Ok(s)
}

/// Lines of a Triangle file without comments and blanks, with their 1-based line numbers.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("");
        let f: Vec<&str> = l.split_whitespace().collect();
        (!f.is_empty()).then_some((i + 1, f))
    })
}

fn err(file: &str, line: usize, message: impl Into<String>) -> MeshError {
    MeshError::Io {
        file: file.to_string(),
        line,
        message: message.into(),
    }
}

fn num<T: std::str::FromStr>(
    file: &str,
    line: usize,
    f: &[&str],
    k: usize,
) -> Result<T, MeshError> {
    f.get(k)
        .ok_or_else(|| err(file, line, format!("missing field {}", k + 1)))?
        .parse()
        .map_err(|_| {
            err(
                file,
                line,
                format!("field {} ({:?}) is not a number", k + 1, f[k]),
            )
        })
}

/// The most entries reserved up front from a file header's count.
const RESERVE_CAP: usize = 1 << 16;

/// Parses `.node` content (or the vertex block of a `.poly`): points, markers, the first index
/// (0 or 1), and the remaining lines.
#[allow(clippy::type_complexity)]
fn parse_nodes<'a>(
    file: &str,
    lines: &mut impl Iterator<Item = (usize, Vec<&'a str>)>,
) -> Result<(Vec<Point>, Vec<i64>, usize), MeshError> {
    let (ln, head) = lines.next().ok_or_else(|| err(file, 0, "empty file"))?;
    let n: usize = num(file, ln, &head, 0)?;
    let attrs: usize = if head.len() > 2 {
        num(file, ln, &head, 2)?
    } else {
        0
    };
    let markers: usize = if head.len() > 3 {
        num(file, ln, &head, 3)?
    } else {
        0
    };
    // A header may claim any count: reserve a bounded amount and let the vectors grow.
    let reserve = n.min(RESERVE_CAP);
    let mut pts = Vec::with_capacity(reserve);
    let mut marks = Vec::with_capacity(reserve);
    let mut base = 0;
    for k in 0..n {
        let (ln, f) = lines
            .next()
            .ok_or_else(|| err(file, ln, format!("expected {n} vertices, found {k}")))?;
        let idx: usize = num(file, ln, &f, 0)?;
        if k == 0 {
            base = idx;
        }
        if idx != k + base {
            return Err(err(
                file,
                ln,
                format!("vertex number {idx}, expected {}", k + base),
            ));
        }
        let x: f64 = num(file, ln, &f, 1)?;
        let y: f64 = num(file, ln, &f, 2)?;
        if !x.is_finite() || !y.is_finite() {
            return Err(err(file, ln, "non-finite coordinate"));
        }
        pts.push(Point::new(x, y));
        marks.push(if markers > 0 {
            num(file, ln, &f, 3 + attrs)?
        } else {
            0
        });
    }
    Ok((pts, marks, base))
}

/// Builds a mesh from `.node` and `.ele` contents and optionally a `.poly` whose segment
/// markers tag the boundary edges. Without a `.poly` (or for boundary edges it does not list),
/// an edge is tagged from its end vertices' markers (the goal/obstacle/wall marker both share,
/// the one of either end otherwise). Clockwise triangles are reoriented.
pub fn from_triangle(node: &str, ele: &str, poly: Option<&str>) -> Result<Mesh, MeshError> {
    let mut lines = data_lines(node);
    let (vertices, marks, base) = parse_nodes(".node", &mut lines)?;
    let nv = vertices.len();
    let mut lines = data_lines(ele);
    let (ln, head) = lines.next().ok_or_else(|| err(".ele", 0, "empty file"))?;
    let nt: usize = num(".ele", ln, &head, 0)?;
    let mut triangles = Vec::with_capacity(nt.min(RESERVE_CAP));
    for k in 0..nt {
        let (ln, f) = lines
            .next()
            .ok_or_else(|| err(".ele", ln, format!("expected {nt} triangles, found {k}")))?;
        let mut t = [0u32; 3];
        for (j, slot) in t.iter_mut().enumerate() {
            let v: usize = num(".ele", ln, &f, j + 1)?;
            if v < base || v - base >= nv {
                return Err(err(".ele", ln, format!("vertex {v} does not exist")));
            }
            *slot = (v - base) as u32;
        }
        let [a, b, c] = t.map(|v| vertices[v as usize]);
        if crate::geom::twice_signed_area(a, b, c) < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    let mut seg_tags: HashMap<(u32, u32), BoundaryTag> = HashMap::new();
    if let Some(poly) = poly {
        let mut lines = data_lines(poly);
        let (pverts, _, pbase) = parse_nodes(".poly", &mut lines)?;
        if !pverts.is_empty() && pverts.len() != nv {
            return Err(err(
                ".poly",
                1,
                format!("{} vertices, the .node file has {nv}", pverts.len()),
            ));
        }
        let pbase = if pverts.is_empty() { base } else { pbase };
        if let Some((ln, head)) = lines.next() {
            let ns: usize = num(".poly", ln, &head, 0)?;
            let has_marker = head.len() > 1 && num::<usize>(".poly", ln, &head, 1)? > 0;
            for k in 0..ns {
                let (ln, f) = lines.next().ok_or_else(|| {
                    err(".poly", ln, format!("expected {ns} segments, found {k}"))
                })?;
                let a: usize = num(".poly", ln, &f, 1)?;
                let b: usize = num(".poly", ln, &f, 2)?;
                if a < pbase || b < pbase || a - pbase >= nv || b - pbase >= nv {
                    return Err(err(".poly", ln, "segment refers to a missing vertex"));
                }
                if has_marker {
                    let m: i64 = num(".poly", ln, &f, 3)?;
                    if let Some(tag) = tag_of_marker(m) {
                        let (a, b) = ((a - pbase) as u32, (b - pbase) as u32);
                        seg_tags.insert((a.min(b), a.max(b)), tag);
                    }
                }
            }
        }
    }
    // Boundary edges: those used by one triangle only.
    let mut count: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * triangles.len());
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut boundary = Vec::new();
    for (&(a, b), &c) in &count {
        if c != 1 {
            continue;
        }
        let tag = seg_tags.get(&(a, b)).copied().or_else(|| {
            let ta = tag_of_marker(marks[a as usize]);
            let tb = tag_of_marker(marks[b as usize]);
            match (ta, tb) {
                (Some(x), Some(y)) if x == y => Some(x),
                (Some(x), _) | (_, Some(x)) => Some(x),
                _ => None,
            }
        });
        let tag = tag.ok_or_else(|| {
            err(
                ".poly",
                0,
                format!("boundary edge ({a}, {b}) has no segment or vertex marker"),
            )
        })?;
        boundary.push((a, b, tag));
    }
    boundary.sort_by_key(|&(a, b, _)| (a, b));
    Ok(Mesh::from_parts(vertices, triangles, &boundary)?)
}

fn write(path: &Path, text: &str) -> Result<(), MeshError> {
    std::fs::write(path, text).map_err(|e| err(&path.display().to_string(), 0, e.to_string()))
}

fn read(path: &Path) -> Result<String, MeshError> {
    std::fs::read_to_string(path).map_err(|e| err(&path.display().to_string(), 0, e.to_string()))
}

/// Writes `base.node`, `base.ele` and `base.poly`.
pub fn write_files(mesh: &Mesh, base: &Path) -> Result<(), MeshError> {
    write(&base.with_extension("node"), &to_node(mesh)?)?;
    write(&base.with_extension("ele"), &to_ele(mesh))?;
    write(&base.with_extension("poly"), &to_poly(mesh)?)
}

/// Reads `base.node`, `base.ele` and, if it exists, `base.poly` (see [`from_triangle`]).
pub fn read_files(base: &Path) -> Result<Mesh, MeshError> {
    let node = read(&base.with_extension("node"))?;
    let ele = read(&base.with_extension("ele"))?;
    let poly_path = base.with_extension("poly");
    let poly = if poly_path.exists() {
        Some(read(&poly_path)?)
    } else {
        None
    };
    from_triangle(&node, &ele, poly.as_deref())
}

/// Reads `FILE`'s `(a, b, marker)` segment lines after a `<count> <markers>` header (a
/// `.poly`'s segment block or a `.edge` file), as 0-based vertex positions.
fn marked_segments<'a>(
    file: &str,
    lines: &mut impl Iterator<Item = (usize, Vec<&'a str>)>,
    base: usize,
    nv: usize,
) -> Result<Vec<(u32, u32, i64)>, MeshError> {
    let Some((ln, head)) = lines.next() else {
        return Ok(Vec::new());
    };
    let ns: usize = num(file, ln, &head, 0)?;
    let has_marker = head.len() > 1 && num::<usize>(file, ln, &head, 1)? > 0;
    let mut out = Vec::with_capacity(ns.min(RESERVE_CAP));
    let mut last = ln;
    for k in 0..ns {
        let (ln, f) = lines
            .next()
            .ok_or_else(|| err(file, last, format!("expected {ns} segments, found {k}")))?;
        last = ln;
        let a: usize = num(file, ln, &f, 1)?;
        let b: usize = num(file, ln, &f, 2)?;
        if a < base || b < base || a - base >= nv || b - base >= nv {
            return Err(err(file, ln, "segment refers to a missing vertex"));
        }
        let m: i64 = if has_marker { num(file, ln, &f, 3)? } else { 0 };
        out.push(((a - base) as u32, (b - base) as u32, m));
    }
    Ok(out)
}

/// Reads a mesh made by Triangle (or written in its formats): `BASE.node` and `BASE.ele`,
/// with boundary markers from `BASE.poly`'s segments if it exists, else from `BASE.edge`
/// if it exists, else from the `.node` vertex markers (an edge whose two ends share a
/// non-zero marker has it). Marker 0 means none. `.ele` files with six nodes per triangle
/// (`-o2`) are read by their corners.
pub fn read_triangle_mesh(base: &Path) -> Result<ImportedMesh, MeshError> {
    // `A.1` names `A.1.node`: the extension is appended, not replaced.
    let with = |ext: &str| {
        let mut p = base.as_os_str().to_owned();
        p.push(".");
        p.push(ext);
        std::path::PathBuf::from(p)
    };
    let node_path = with("node");
    let ele_path = with("ele");
    let node_name = node_path.display().to_string();
    let ele_name = ele_path.display().to_string();
    let node = read(&node_path)?;
    let ele = read(&ele_path)?;
    let (vertices, marks, vbase) = parse_nodes(&node_name, &mut data_lines(&node))?;
    let nv = vertices.len();
    let mut lines = data_lines(&ele);
    let (ln, head) = lines
        .next()
        .ok_or_else(|| err(&ele_name, 0, "empty file"))?;
    let nt: usize = num(&ele_name, ln, &head, 0)?;
    let corners: usize = if head.len() > 1 {
        num(&ele_name, ln, &head, 1)?
    } else {
        3
    };
    if corners < 3 {
        return Err(err(&ele_name, ln, format!("{corners} nodes per triangle")));
    }
    let mut triangles = Vec::with_capacity(nt.min(RESERVE_CAP));
    let mut tbase = 0;
    let mut last = ln;
    for k in 0..nt {
        let (ln, f) = lines.next().ok_or_else(|| {
            err(
                &ele_name,
                last,
                format!("expected {nt} triangles, found {k}"),
            )
        })?;
        last = ln;
        if k == 0 {
            tbase = num(&ele_name, ln, &f, 0)?;
        }
        let mut t = [0u32; 3];
        for (j, slot) in t.iter_mut().enumerate() {
            let v: usize = num(&ele_name, ln, &f, j + 1)?;
            if v < vbase || v - vbase >= nv {
                return Err(err(
                    &ele_name,
                    ln,
                    format!("triangle refers to vertex {v}, which does not exist"),
                ));
            }
            *slot = (v - vbase) as u32;
        }
        triangles.push(t);
    }
    let poly_path = with("poly");
    let edge_path = with("edge");
    let mut segments: HashMap<(u32, u32), i64> = HashMap::new();
    let from_segments = if poly_path.exists() {
        let name = poly_path.display().to_string();
        let text = read(&poly_path)?;
        let mut lines = data_lines(&text);
        let (pverts, _, pbase) = parse_nodes(&name, &mut lines)?;
        if !pverts.is_empty() && pverts.len() != nv {
            return Err(err(
                &name,
                1,
                format!("{} vertices, the .node file has {nv}", pverts.len()),
            ));
        }
        let pbase = if pverts.is_empty() { vbase } else { pbase };
        Some(marked_segments(&name, &mut lines, pbase, nv)?)
    } else if edge_path.exists() {
        let name = edge_path.display().to_string();
        let text = read(&edge_path)?;
        Some(marked_segments(&name, &mut data_lines(&text), vbase, nv)?)
    } else {
        None
    };
    for (a, b, m) in from_segments.iter().flatten() {
        if *m != 0 {
            segments.insert(((*a).min(*b), (*a).max(*b)), *m);
        }
    }
    let use_vertices = from_segments.is_none();
    let marker = |a: u32, b: u32| -> Option<i64> {
        if use_vertices {
            let (ma, mb) = (marks[a as usize], marks[b as usize]);
            (ma != 0 && ma == mb).then_some(ma)
        } else {
            segments.get(&(a.min(b), a.max(b))).copied()
        }
    };
    ImportedMesh::new(
        &ele_name,
        vertices,
        triangles,
        tbase,
        &|v| v as usize + vbase,
        &marker,
        Vec::new(),
    )
}
