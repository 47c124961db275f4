//! Test meshes built with `Mesh::from_parts`: a structured grid over a square with a square
//! hole (right isosceles triangles, so Delaunay), sides tagged separately.

use harmonic_mesh::{BoundaryTag, Mesh, Point};

/// Which side of the outer square or the hole an edge lies on.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
    Hole,
}

/// The square [x0, x0 + 2]×[y0, y0 + 2] minus the hole [x0 + 0.5, x0 + 1.5]×[y0 + 0.5, y0 + 1.5],
/// `n` cells per side (`n` a multiple of 4), each cell split along a diagonal chosen in
/// alternating directions. `tag(side)` gives the tag of each side.
pub fn square_with_hole(n: usize, x0: f64, y0: f64, tag: impl Fn(Side) -> BoundaryTag) -> Mesh {
    assert!(n.is_multiple_of(4));
    let h = 2.0 / n as f64;
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let in_hole = |i: usize, j: usize| {
        // cell (i, j) = [i h, (i+1) h] × [j h, (j+1) h]
        i >= n / 4 && i < 3 * n / 4 && j >= n / 4 && j < 3 * n / 4
    };
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            vertices.push(Point::new(x0 + i as f64 * h, y0 + j as f64 * h));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if in_hole(i, j) {
                continue;
            }
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            } else {
                triangles.push([a, b, d]);
                triangles.push([b, c, d]);
            }
        }
    }
    let mut boundary = Vec::new();
    for k in 0..n {
        boundary.push((id(k, 0), id(k + 1, 0), tag(Side::Bottom)));
        boundary.push((id(k, n), id(k + 1, n), tag(Side::Top)));
        boundary.push((id(0, k), id(0, k + 1), tag(Side::Left)));
        boundary.push((id(n, k), id(n, k + 1), tag(Side::Right)));
    }
    let (lo, hi) = (n / 4, 3 * n / 4);
    for k in lo..hi {
        boundary.push((id(k, lo), id(k + 1, lo), tag(Side::Hole)));
        boundary.push((id(k, hi), id(k + 1, hi), tag(Side::Hole)));
        boundary.push((id(lo, k), id(lo, k + 1), tag(Side::Hole)));
        boundary.push((id(hi, k), id(hi, k + 1), tag(Side::Hole)));
    }
    // Drop vertices strictly inside the hole by remapping (keeps vertex order).
    let mut used = vec![false; vertices.len()];
    for t in &triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut new_id = vec![u32::MAX; vertices.len()];
    let mut kept = Vec::new();
    for (v, p) in vertices.iter().enumerate() {
        if used[v] {
            new_id[v] = kept.len() as u32;
            kept.push(*p);
        }
    }
    let triangles = triangles
        .into_iter()
        .map(|t| t.map(|v| new_id[v as usize]))
        .collect();
    let boundary: Vec<_> = boundary
        .into_iter()
        .map(|(a, b, t)| (new_id[a as usize], new_id[b as usize], t))
        .collect();
    Mesh::from_parts(kept, triangles, &boundary).expect("valid structured mesh")
}

/// The usual split: left side goal 0, hole obstacle 0, other sides walls.
pub fn three_part_tags(side: Side) -> BoundaryTag {
    match side {
        Side::Left => BoundaryTag::Goal(0),
        Side::Hole => BoundaryTag::Obstacle(0),
        _ => BoundaryTag::Wall,
    }
}
