//! Output: VTK unstructured grids (`.vtu`, ASCII) with point data, and an SVG of the three
//! orthographic projections (xy, xz, yz) of the obstacle and goal boundary faces and of paths.

use std::fmt::Write as _;

use harmonic_types::BoundaryTag;

use crate::error::VolumeError;
use crate::solid::Point;
use harmonic_types::TetMesh;

/// Point data for [`vtu_string`].
#[derive(Clone, Copy, Debug)]
pub enum PointData<'a> {
    /// One number per vertex.
    Scalar(&'a str, &'a [f64]),
    /// One vector per vertex.
    Vector(&'a str, &'a [[f64; 3]]),
}

/// The mesh as a VTK XML unstructured grid (tetrahedra, cell type 10) with point data and
/// a cell scalar `tet`. Fails if a data array does not have one entry per vertex.
pub fn vtu_string(mesh: &TetMesh, data: &[PointData<'_>]) -> Result<String, VolumeError> {
    let nv = mesh.vertices().len();
    let nt = mesh.tetrahedra().len();
    let mut s = String::with_capacity(64 * nv + 48 * nt);
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{nv}\" NumberOfCells=\"{nt}\">"
    );
    s.push_str("<PointData>\n");
    for d in data {
        match d {
            PointData::Scalar(name, v) => {
                if v.len() != nv {
                    return Err(VolumeError::PointDataLength {
                        name: name.to_string(),
                        entries: v.len(),
                        vertices: nv,
                    });
                }
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
                );
                for x in *v {
                    let _ = writeln!(s, "{x:e}");
                }
            }
            PointData::Vector(name, v) => {
                if v.len() != nv {
                    return Err(VolumeError::PointDataLength {
                        name: name.to_string(),
                        entries: v.len(),
                        vertices: nv,
                    });
                }
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
                );
                for x in *v {
                    let _ = writeln!(s, "{:e} {:e} {:e}", x[0], x[1], x[2]);
                }
            }
        }
        s.push_str("</DataArray>\n");
    }
    s.push_str("</PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in mesh.vertices() {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in mesh.tetrahedra() {
        let _ = writeln!(s, "{} {} {} {}", t[0], t[1], t[2], t[3]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=nt {
        let _ = writeln!(s, "{}", 4 * i);
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..nt {
        s.push_str("10\n");
    }
    s.push_str("</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    Ok(s)
}

/// Writes [`vtu_string`] to `path`.
pub fn write_vtu(path: &str, mesh: &TetMesh, data: &[PointData<'_>]) -> Result<(), VolumeError> {
    std::fs::write(path, vtu_string(mesh, data)?).map_err(|source| VolumeError::Io {
        path: path.to_string(),
        source,
    })
}

/// Three orthographic projections side by side (xy, xz, yz): obstacle faces in grey, goal
/// faces in green (both translucent, so depth shows as density), the mesh's bounding box as
/// each panel's frame, and the paths as polylines (start dots).
pub fn projections_svg(mesh: &TetMesh, paths: &[Vec<Point>]) -> String {
    let (lo, hi) = mesh.bounds();
    let panel = 300.0;
    let pad = 20.0;
    let planes: [(usize, usize, &str); 3] = [(0, 1, "xy"), (0, 2, "xz"), (1, 2, "yz")];
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\">",
        3.0 * (panel + 2.0 * pad),
        panel + 3.0 * pad,
        3.0 * (panel + 2.0 * pad),
        panel + 3.0 * pad
    );
    let colors = [
        "#d62728", "#1f77b4", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
    ];
    for (n, &(a, b, name)) in planes.iter().enumerate() {
        let ox = n as f64 * (panel + 2.0 * pad) + pad;
        let oy = 2.0 * pad;
        let scale = panel / (hi[a] - lo[a]).max(hi[b] - lo[b]).max(1e-300);
        let map = |p: &Point| {
            (
                ox + (p[a] - lo[a]) * scale,
                oy + panel - (p[b] - lo[b]) * scale,
            )
        };
        let _ = writeln!(
            s,
            "<text x=\"{ox}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"14\">{name}</text>",
            pad
        );
        let _ = writeln!(
            s,
            "<rect x=\"{ox}\" y=\"{oy}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>",
            (hi[a] - lo[a]) * scale,
            (hi[b] - lo[b]) * scale
        );
        for f in mesh.boundary_faces() {
            let fill = match f.tag {
                BoundaryTag::Wall => continue,
                BoundaryTag::Obstacle(_) => "#555555",
                BoundaryTag::Goal(_) => "#2ca02c",
            };
            let corners = f.vertices.map(|v| mesh.vertices()[v as usize]);
            let q = corners.map(|p| map(&p));
            // A face seen edge-on (a wall parallel to the viewing axis) has no area in this
            // projection: draw its outline instead, so such obstacles still show.
            let area3 = (corners[1] - corners[0])
                .cross(&(corners[2] - corners[0]))
                .norm();
            let area2 = ((q[1].0 - q[0].0) * (q[2].1 - q[0].1)
                - (q[1].1 - q[0].1) * (q[2].0 - q[0].0))
                .abs();
            let edge_on = area2 < 0.05 * area3 * scale * scale;
            let (fill_opacity, stroke) = if edge_on {
                (
                    "0",
                    format!("stroke=\"{fill}\" stroke-opacity=\"0.5\" stroke-width=\"0.8\""),
                )
            } else {
                ("0.06", "stroke=\"none\"".to_string())
            };
            let _ = writeln!(
                s,
                "<polygon points=\"{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}\" fill=\"{fill}\" fill-opacity=\"{fill_opacity}\" {stroke}/>",
                q[0].0, q[0].1, q[1].0, q[1].1, q[2].0, q[2].1
            );
        }
        for (i, path) in paths.iter().enumerate() {
            let color = colors[i % colors.len()];
            let pts: Vec<String> = path
                .iter()
                .map(|p| {
                    let (x, y) = map(p);
                    format!("{x:.2},{y:.2}")
                })
                .collect();
            let _ = writeln!(
                s,
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"1.5\"/>",
                pts.join(" ")
            );
            if let Some(p) = path.first() {
                let (x, y) = map(p);
                let _ = writeln!(
                    s,
                    "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"3\" fill=\"{color}\"/>"
                );
            }
        }
    }
    s.push_str("</svg>\n");
    s
}

/// Writes [`projections_svg`] to `path`.
pub fn write_projections_svg(
    path: &str,
    mesh: &TetMesh,
    paths: &[Vec<Point>],
) -> Result<(), VolumeError> {
    std::fs::write(path, projections_svg(mesh, paths)).map_err(|source| VolumeError::Io {
        path: path.to_string(),
        source,
    })
}
