//! Graded stuffing of a periodic domain: a plate thinner than the lattice runs the whole
//! period (across the seam), so the lattice must be refined at both ends of the slab alike.

use harmonic_volume::{
    BoundaryTag, Grading, ImplicitDomain, PeriodicMesh, Point, SEAM_PART, StuffingOptions,
    longest_edge, signed_volume, stuff_periodic,
};

const H: f64 = 0.5;
const CELLS: usize = 12;
const PERIOD: f64 = CELLS as f64 * H;

/// A 6 × 3 × 3 box, periodic along x, less a plate 0.1 thick (y 1.3..1.4, between the
/// lattice's planes at y = 1.25 and 1.5) and 2 wide (z 0.5..2.5) along the whole period.
struct Plate {
    graded: bool,
}

impl Plate {
    /// The plate's signed distance (negative inside), a box's, exact enough off its edges.
    fn plate(p: &Point) -> f64 {
        ((p.y - 1.35).abs() - 0.05).max((p.z - 1.5).abs() - 1.0)
    }
}

impl ImplicitDomain for Plate {
    fn value(&self, p: &Point) -> f64 {
        let walls = (-p.y).max(p.y - 3.0).max(-p.z).max(p.z - 3.0);
        walls.max(-Self::plate(p))
    }
    fn tag(&self, p: &Point) -> BoundaryTag {
        if Self::plate(p).abs() < 1e-6 {
            BoundaryTag::Obstacle(0)
        } else {
            BoundaryTag::Wall
        }
    }
    fn bounds(&self) -> (Point, Point) {
        (Point::new(0.0, 0.0, 0.0), Point::new(PERIOD, 3.0, 3.0))
    }
    fn grading(&self, spacing: f64) -> Option<Grading<'_>> {
        if !self.graded {
            return None;
        }
        let floor = spacing / 8.0;
        Some(Grading {
            want: Box::new(move |p: &[Point; 4]| {
                let s = longest_edge(p);
                let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
                s > floor && Self::plate(&c).abs() < s
            }),
            rank: Box::new(|c: &Point| Self::plate(c).abs()),
            known: None,
        })
    }
}

fn mesh(graded: bool) -> (PeriodicMesh, usize) {
    let domain = Plate { graded };
    let stuffed = stuff_periodic(
        &domain,
        &StuffingOptions {
            spacing: H,
            max_tetrahedra: 2_000_000,
        },
        [Some(CELLS), None, None],
    )
    .expect("stuffing");
    let graded = stuffed.stuffed.graded;
    let mesh = PeriodicMesh::new(&stuffed, 1, &|p| domain.tag(p)).expect("periodic mesh");
    (mesh, graded)
}

#[test]
fn the_uniform_lattice_loses_the_plate() {
    let (mesh, graded) = mesh(false);
    assert_eq!(graded, 0);
    assert!(
        mesh.slab.volume() > 53.9,
        "the plate slips between the lattice's planes: {}",
        mesh.slab.volume()
    );
}

#[test]
fn grading_resolves_the_plate_across_the_seam() {
    let (mesh, graded) = mesh(true);
    assert!(graded > 0);
    let slab = &mesh.slab;
    let exact = PERIOD * 9.0 - 0.1 * PERIOD * 2.0;
    assert!(
        (slab.volume() - exact).abs() < 0.1,
        "volume {} vs {exact}",
        slab.volume()
    );
    // Every tetrahedron positive and outside the plate (stuffing cuts a sharp edge across, so
    // away from the plate's long edges at z = 0.5 and 2.5).
    let v = slab.vertices();
    for t in slab.tetrahedra() {
        let p = t.map(|i| v[i as usize]);
        assert!(signed_volume(&p[0], &p[1], &p[2], &p[3]) > 0.0);
        let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
        assert!(
            Plate::plate(&c) > -1e-9 || (c.z - 1.5).abs() > 0.9,
            "a tetrahedron inside the plate at {c:?}"
        );
    }
    // The plate has faces at both ends of the slab and in its middle.
    let mut plate_x: Vec<f64> = slab
        .boundary_faces()
        .iter()
        .filter(|f| f.tag == BoundaryTag::Obstacle(0))
        .map(|f| f.vertices.iter().map(|&i| v[i as usize].x).sum::<f64>() / 3.0)
        .collect();
    plate_x.sort_by(f64::total_cmp);
    assert!(plate_x.first().is_some_and(|&x| x < 0.3 * H));
    assert!(plate_x.last().is_some_and(|&x| x > PERIOD - 0.3 * H));
    // Identified vertices are one period apart, and the covering's copies glue into one
    // conforming mesh: its only seam faces are its two outer ends, as many as the slab's.
    for (a, &b) in mesh.images.iter().enumerate() {
        let (p, q) = (v[a], v[b as usize]);
        let k = ((q.x - p.x) / PERIOD).round();
        assert!(
            (q.x - p.x - k * PERIOD).abs() < 1e-9
                && (q.y - p.y).abs() < 1e-9
                && (q.z - p.z).abs() < 1e-9,
            "{p:?} is identified with {q:?}"
        );
    }
    let covering_seams = mesh
        .covering
        .boundary_faces()
        .iter()
        .filter(|f| f.tag == BoundaryTag::Obstacle(SEAM_PART))
        .count();
    assert_eq!(covering_seams, mesh.seam_faces);
    // The copies fill three periods.
    assert!((mesh.covering.volume() - 3.0 * slab.volume()).abs() < 1e-6 * slab.volume());
}
