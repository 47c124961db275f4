//! A coarse mesh and its refinements: the levels of a geometric multigrid.

use std::sync::Arc;

use crate::Mesh;
use crate::error::MeshDataError;

/// A coarse mesh and its uniform refinements, coarse to fine: the levels of a geometric
/// multigrid, and for every vertex of a finer level the two vertices of the level below it
/// lies between (`[a, a]` for a vertex kept, `[a, b]` for the midpoint of edge `a b`).
/// The mesher builds it (`harmonic_mesh::uniform_hierarchy`); the solvers read it.
#[derive(Clone, Debug)]
pub struct MeshHierarchy {
    levels: Vec<Arc<Mesh>>,
    /// `parents[l]`: the parents (in level `l`) of level `l + 1`'s vertices.
    parents: Vec<Vec<[u32; 2]>>,
}

impl MeshHierarchy {
    /// The hierarchy of `levels` (coarsest first, at least one) and `parents[l]`, the parents
    /// in level `l` of level `l + 1`'s vertices. Checks that there is one parent pair per
    /// finer vertex and that every parent exists.
    pub fn from_levels(
        levels: Vec<Arc<Mesh>>,
        parents: Vec<Vec<[u32; 2]>>,
    ) -> Result<Self, MeshDataError> {
        if levels.is_empty() || parents.len() + 1 != levels.len() {
            return Err(MeshDataError::LevelCount {
                levels: levels.len(),
                parents: parents.len(),
            });
        }
        for (l, p) in parents.iter().enumerate() {
            let (coarse, fine) = (levels[l].vertices().len(), levels[l + 1].vertices().len());
            if p.len() != fine {
                return Err(MeshDataError::ParentCount {
                    level: l + 1,
                    given: p.len(),
                    vertices: fine,
                });
            }
            if let Some(v) = p
                .iter()
                .position(|ab| ab.iter().any(|&x| x as usize >= coarse))
            {
                return Err(MeshDataError::VertexOutOfRange {
                    element: crate::Element::Triangle,
                    index: v,
                    vertex: p[v][0].max(p[v][1]),
                    vertices: coarse,
                });
            }
        }
        Ok(Self { levels, parents })
    }

    /// The meshes, coarsest first.
    pub fn levels(&self) -> &[Arc<Mesh>] {
        &self.levels
    }

    /// The finest mesh.
    pub fn finest(&self) -> &Arc<Mesh> {
        &self.levels[self.levels.len() - 1]
    }

    /// For each vertex of level `level` (at least 1), its parents in level `level − 1`
    /// ; empty for level 0 or past the finest.
    pub fn parents(&self, level: usize) -> &[[u32; 2]] {
        level
            .checked_sub(1)
            .and_then(|l| self.parents.get(l))
            .map_or(&[], Vec::as_slice)
    }
}
