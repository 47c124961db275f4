//! gmsh's `.msh` files (format 4.1, ASCII or binary), read with the `mshio` crate.
//!
//! The triangles (`Tri3`, or the corners of `Tri6`) of every surface are the mesh; the line
//! elements (`Lin2`, `Lin3`) on its boundary mark their edges with the first physical group
//! of the curve they belong to, and `$PhysicalNames` (which `mshio` does not read; a few
//! lines parsed here) names those groups. z coordinates are ignored.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use mshio::mshfile::ElementType;

use super::ImportedMesh;
use crate::{MeshError, Point};

fn input(file: &str, message: impl Into<String>) -> MeshError {
    MeshError::Input {
        file: file.to_string(),
        message: message.into(),
    }
}

/// The `(tag, name)` pairs of the dimension-1 physical groups in a `$PhysicalNames` section
/// (ASCII in binary files too): lines `DIM TAG "NAME"`.
fn physical_names(bytes: &[u8]) -> Vec<(i64, String)> {
    let text = String::from_utf8_lossy(bytes);
    let Some(start) = text.find("$PhysicalNames") else {
        return Vec::new();
    };
    let body = &text[start..];
    let end = body.find("$EndPhysicalNames").unwrap_or(body.len());
    body[..end]
        .lines()
        .skip(2)
        .filter_map(|l| {
            let mut f = l.trim().splitn(3, ' ');
            let dim: i64 = f.next()?.parse().ok()?;
            let tag: i64 = f.next()?.parse().ok()?;
            let name = f.next()?.trim().trim_matches('"').to_string();
            (dim == 1).then_some((tag, name))
        })
        .collect()
}

/// Reads a gmsh `.msh` file (see the module documentation).
pub fn read_msh(path: &Path) -> Result<ImportedMesh, MeshError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| input(&file, e.to_string()))?;
    from_msh_bytes(&bytes, &file)
}

/// Parses the bytes of a `.msh` file named `file`.
pub fn from_msh_bytes(bytes: &[u8], file: &str) -> Result<ImportedMesh, MeshError> {
    let parsed = catch_unwind(AssertUnwindSafe(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| {
            let kind = e
                .first_msh_error()
                .map_or_else(|| "malformed file".to_string(), |k| k.to_string());
            format!("not a gmsh MSH 4.1 file it can read: {kind}")
        })
    }))
    .map_err(|_| {
        input(
            file,
            "not a gmsh MSH 4.1 file it can read (the parser gave up)",
        )
    })?
    .map_err(|m| input(file, m))?;
    let nodes = parsed
        .data
        .nodes
        .as_ref()
        .ok_or_else(|| input(file, "has no $Nodes section"))?;
    let elements = parsed
        .data
        .elements
        .as_ref()
        .ok_or_else(|| input(file, "has no $Elements section"))?;
    // Node tag → position. Blocks without their own tag map are numbered on from the
    // smallest tag (mshio keeps the map only for sparse numberings).
    let mut position: HashMap<u64, u32> = HashMap::new();
    let mut vertices: Vec<Point> = Vec::new();
    let mut next_tag = nodes.min_node_tag;
    for block in &nodes.node_blocks {
        let mut by_index: Vec<u64> = vec![0; block.nodes.len()];
        match &block.node_tags {
            Some(tags) => {
                for (&tag, &i) in tags {
                    if let Some(slot) = by_index.get_mut(i) {
                        *slot = tag;
                    }
                }
            }
            None => {
                for slot in by_index.iter_mut() {
                    *slot = next_tag;
                    next_tag += 1;
                }
            }
        }
        for (node, tag) in block.nodes.iter().zip(by_index) {
            if !(node.x.is_finite() && node.y.is_finite()) {
                return Err(input(
                    file,
                    format!("node {tag} has a non-finite coordinate"),
                ));
            }
            if position.insert(tag, vertices.len() as u32).is_some() {
                return Err(input(file, format!("node {tag} is given twice")));
            }
            vertices.push(Point::new(node.x, node.y));
        }
    }
    let curve_group: HashMap<i32, i64> = parsed
        .data
        .entities
        .as_ref()
        .map(|e| {
            e.curves
                .iter()
                .filter_map(|c| c.physical_tags.first().map(|&p| (c.tag, i64::from(p))))
                .collect()
        })
        .unwrap_or_default();
    let node = |tag: u64, element: u64| {
        position.get(&tag).copied().ok_or_else(|| {
            input(
                file,
                format!("element {element} refers to node {tag}, which does not exist"),
            )
        })
    };
    let mut referenced = vec![false; vertices.len()];
    let mut triangles = Vec::new();
    let mut element_tags = Vec::new();
    let mut lines: HashMap<(u32, u32), i64> = HashMap::new();
    for block in &elements.element_blocks {
        match block.element_type {
            ElementType::Tri3 | ElementType::Tri6 => {
                for e in &block.elements {
                    if e.nodes.len() < 3 {
                        return Err(input(
                            file,
                            format!("triangle {} has too few nodes", e.element_tag),
                        ));
                    }
                    let mut t = [0u32; 3];
                    for (slot, &n) in t.iter_mut().zip(&e.nodes) {
                        *slot = node(n, e.element_tag)?;
                        referenced[*slot as usize] = true;
                    }
                    triangles.push(t);
                    element_tags.push(e.element_tag);
                }
            }
            ElementType::Lin2 | ElementType::Lin3 => {
                let group = curve_group.get(&block.entity_tag).copied();
                for e in &block.elements {
                    if e.nodes.len() < 2 {
                        return Err(input(
                            file,
                            format!("line {} has too few nodes", e.element_tag),
                        ));
                    }
                    let (a, b) = (
                        node(e.nodes[0], e.element_tag)?,
                        node(e.nodes[1], e.element_tag)?,
                    );
                    for &n in &e.nodes {
                        referenced[node(n, e.element_tag)? as usize] = true;
                    }
                    if let Some(group) = group {
                        lines.insert((a.min(b), a.max(b)), group);
                    }
                }
            }
            // Points, and elements of other kinds (quadrangles, volumes) are not planned on.
            ElementType::Pnt => {
                for e in &block.elements {
                    for &n in &e.nodes {
                        referenced[node(n, e.element_tag)? as usize] = true;
                    }
                }
            }
            other => {
                return Err(input(
                    file,
                    format!("has {other:?} elements; only triangles (and lines, points) are read"),
                ));
            }
        }
    }
    let mut tag_of: Vec<u64> = vec![0; vertices.len()];
    for (&tag, &p) in &position {
        tag_of[p as usize] = tag;
    }
    if let Some(v) = referenced.iter().position(|r| !r) {
        return Err(MeshError::UnusedVertex {
            file: file.to_string(),
            vertex: tag_of[v] as usize,
        });
    }
    // Nodes of points or lines only (a physical point off the surface) are no mesh vertices:
    // keep the nodes the triangles use, in their order.
    let mut keep = vec![u32::MAX; vertices.len()];
    let mut kept = Vec::new();
    let mut tag_of_kept = Vec::new();
    for t in triangles.iter_mut() {
        for v in t.iter_mut() {
            if keep[*v as usize] == u32::MAX {
                keep[*v as usize] = kept.len() as u32;
                kept.push(vertices[*v as usize]);
                tag_of_kept.push(tag_of[*v as usize]);
            }
            *v = keep[*v as usize];
        }
    }
    let lines: HashMap<(u32, u32), i64> = lines
        .into_iter()
        .filter_map(|((a, b), g)| {
            let (a, b) = (keep[a as usize], keep[b as usize]);
            (a != u32::MAX && b != u32::MAX).then_some(((a.min(b), a.max(b)), g))
        })
        .collect();
    // Triangles are named by their element tags: map positions back for errors.
    let first = element_tags.first().copied().unwrap_or(1) as usize;
    let consecutive = element_tags
        .iter()
        .enumerate()
        .all(|(i, &t)| t as usize == first + i);
    if !consecutive {
        // The imported mesh names triangles by position from `first`; keep the promise of
        // file numbers by checking here what it would report.
        for (i, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|v| kept[v as usize]);
            if crate::geom::twice_signed_area(a, b, c) == 0.0 {
                return Err(MeshError::DegenerateTriangle {
                    file: file.to_string(),
                    triangle: element_tags[i] as usize,
                });
            }
        }
    }
    ImportedMesh::new(
        file,
        kept,
        triangles,
        first,
        &|v| tag_of_kept[v as usize] as usize,
        &|a, b| lines.get(&(a.min(b), a.max(b))).copied(),
        physical_names(bytes),
    )
}
