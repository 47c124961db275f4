//! A triangle mesh read from another tool's files (Triangle's `.node/.ele`, gmsh's `.msh`):
//! validated, oriented, with the marker (Triangle boundary marker or gmsh physical group) of
//! each boundary edge, and turned into a [`Mesh`] once it is known which marker is the goal.

use std::collections::HashMap;

use crate::{BoundaryTag, Mesh, MeshError, Point, geom::twice_signed_area};

/// A mesh made elsewhere, checked: counter-clockwise triangles of positive area, every edge
/// in at most two triangles (on opposite sides), every vertex used.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMesh {
    /// The file it was read from (for error messages).
    pub file: String,
    /// The vertices.
    pub vertices: Vec<Point>,
    /// The triangles, counter-clockwise (clockwise ones of the file were turned).
    pub triangles: Vec<[u32; 3]>,
    /// Every boundary edge (free space on the left of `[a, b]`) with its marker, if any.
    pub boundary: Vec<([u32; 2], Option<i64>)>,
    /// Names of markers (gmsh's physical names of curves).
    pub names: Vec<(i64, String)>,
}

/// Directed-edge key.
fn key(a: u32, b: u32) -> u64 {
    (u64::from(a) << 32) | u64::from(b)
}

impl ImportedMesh {
    /// Checks `triangles` (vertex positions in `vertices`) and finds the boundary edges, each
    /// marked by `marker(a, b)` (either order). Errors name triangles and vertices as the file
    /// numbers them: from `triangle_base` and `vertex_base` (`vertex_name` maps a position to
    /// the file's number, for files whose numbers are not consecutive).
    pub fn new(
        file: &str,
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        triangle_base: usize,
        vertex_name: &dyn Fn(u32) -> usize,
        marker: &dyn Fn(u32, u32) -> Option<i64>,
        names: Vec<(i64, String)>,
    ) -> Result<ImportedMesh, MeshError> {
        let nv = vertices.len();
        let mut triangles = triangles;
        let mut used = vec![false; nv];
        for (k, t) in triangles.iter_mut().enumerate() {
            if let Some(&v) = t.iter().find(|&&v| v as usize >= nv) {
                return Err(MeshError::Input {
                    file: file.to_string(),
                    message: format!(
                        "triangle {} refers to vertex position {v}, beyond the {nv} vertices",
                        k + triangle_base
                    ),
                });
            }
            let [a, b, c] = t.map(|v| vertices[v as usize]);
            let o = twice_signed_area(a, b, c);
            if o == 0.0 || !o.is_finite() || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(MeshError::DegenerateTriangle {
                    file: file.to_string(),
                    triangle: k + triangle_base,
                });
            }
            if o < 0.0 {
                t.swap(1, 2);
            }
            for &v in t.iter() {
                used[v as usize] = true;
            }
        }
        if let Some(v) = used.iter().position(|u| !u) {
            return Err(MeshError::UnusedVertex {
                file: file.to_string(),
                vertex: vertex_name(v as u32),
            });
        }
        if triangles.is_empty() {
            return Err(MeshError::Input {
                file: file.to_string(),
                message: "has no triangles".to_string(),
            });
        }
        // Directed edges: each at most once; an undirected edge in at most two triangles.
        let mut directed: HashMap<u64, u32> = HashMap::with_capacity(3 * triangles.len());
        for (k, t) in triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                if directed.insert(key(a, b), k as u32).is_some() {
                    let count = 2 + usize::from(directed.contains_key(&key(b, a)));
                    return Err(MeshError::NonManifoldEdge {
                        file: file.to_string(),
                        a: vertex_name(a),
                        b: vertex_name(b),
                        count,
                    });
                }
            }
        }
        let mut boundary = Vec::new();
        for t in &triangles {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                if !directed.contains_key(&key(b, a)) {
                    boundary.push(([a, b], marker(a, b)));
                }
            }
        }
        Ok(ImportedMesh {
            file: file.to_string(),
            vertices,
            triangles,
            boundary,
            names,
        })
    }

    /// The distinct markers of the boundary edges, in increasing order.
    pub fn markers(&self) -> Vec<i64> {
        let mut m: Vec<i64> = self.boundary.iter().filter_map(|e| e.1).collect();
        m.sort_unstable();
        m.dedup();
        m
    }

    /// The marker `tag` names: a number, or a name from [`ImportedMesh::names`]. An error
    /// (listing the markers there are) if no boundary edge carries it.
    pub fn marker(&self, tag: &str) -> Result<i64, MeshError> {
        let tag = tag.trim();
        let found = self
            .names
            .iter()
            .find(|(_, n)| n == tag)
            .map(|&(m, _)| m)
            .or_else(|| tag.parse::<i64>().ok());
        let markers = self.markers();
        match found {
            Some(m) if markers.contains(&m) => Ok(m),
            _ => {
                let list: Vec<String> = markers
                    .iter()
                    .map(|m| match self.names.iter().find(|(k, _)| k == m) {
                        Some((_, n)) => format!("{m} ({n:?})"),
                        None => m.to_string(),
                    })
                    .collect();
                Err(MeshError::Input {
                    file: self.file.clone(),
                    message: format!(
                        "no boundary edge has the tag {tag:?}; the boundary's tags are: {}",
                        if list.is_empty() {
                            "none".to_string()
                        } else {
                            list.join(", ")
                        }
                    ),
                })
            }
        }
    }

    /// The mesh with boundary edges of marker `goal` tagged [`BoundaryTag::Goal`]`(0)` and
    /// every other boundary edge [`BoundaryTag::Wall`].
    pub fn to_mesh(&self, goal: Option<i64>) -> Result<Mesh, MeshError> {
        let tags: Vec<(u32, u32, BoundaryTag)> = self
            .boundary
            .iter()
            .map(|&([a, b], m)| {
                let tag = if goal.is_some() && m == goal {
                    BoundaryTag::Goal(0)
                } else {
                    BoundaryTag::Wall
                };
                (a, b, tag)
            })
            .collect();
        Ok(Mesh::from_parts(
            self.vertices.clone(),
            self.triangles.clone(),
            &tags,
        )?)
    }
}
