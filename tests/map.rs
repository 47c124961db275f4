//! Occupancy-grid maps: the bundled warehouse map, tracing, planning on it, the command line
//! and the errors of bad maps.
//!
//! The warehouse map in `meshes/` is made by [`warehouse_pixels`]; regenerate it with
//! `cargo test --release --test map -- --ignored write_warehouse_map`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use geo::{Contains, Coord, LineString, Polygon};
use harmonic_planner::fem::{Assembler, AssemblyOptions, BoundaryConditions};
use harmonic_planner::map::{
    Cell, MapError, MapMesher, MapOptions, OccupancyMap, Snap, UnknownCells,
};
use harmonic_planner::{Planner, PlannerOptions};

const W: usize = 400;
const H: usize = 300;
const FREE: u8 = 254;
const OCCUPIED: u8 = 0;
const UNKNOWN: u8 = 205;

/// The goal of the warehouse tests, in the office's lower room (world coordinates).
const GOAL: [f64; 2] = [16.5, 1.5];
/// Starts that reach the goal: warehouse corner, an aisle between racks, top aisle, upper office.
const REACHABLE: [[f64; 2]; 4] = [[-0.75, -0.5], [3.0, 4.0], [7.0, 12.0], [13.0, 8.5]];
/// Starts that cannot: inside the closed closet, in the scanned patch outside the building.
const UNREACHABLE: [[f64; 2]; 2] = [[16.4, 11.8], [0.25, -1.3]];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn warehouse_yaml() -> PathBuf {
    root().join("meshes/warehouse_map.yaml")
}

/// A small deterministic generator (linear congruential).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

/// The warehouse map, cells row by row with row 0 at the bottom: 400 × 300 cells at 5 cm.
/// A walled building in unknown surroundings; a warehouse hall with two rows of five racks,
/// pallets, pillars, a hollow column, sensor speckles and an unscanned shadow behind a rack;
/// a wall with two doors to the offices, which a wall with one door splits into a lower room
/// (desks, chairs) and an upper room (a diagonal partition, a round table, an unscanned
/// corner and a closed closet). A patch outside the building was seen through a window.
fn warehouse_cells() -> Vec<u8> {
    let mut g = vec![UNKNOWN; W * H];
    let rect = |g: &mut Vec<u8>, i0: usize, j0: usize, i1: usize, j1: usize, v: u8| {
        for j in j0..j1 {
            for i in i0..i1 {
                g[j * W + i] = v;
            }
        }
    };
    // Building: 4-cell walls, free inside.
    rect(&mut g, 8, 8, 392, 292, OCCUPIED);
    rect(&mut g, 12, 12, 388, 288, FREE);
    // Seen through a window: free cells outside the building.
    rect(&mut g, 30, 0, 60, 7, FREE);
    // Wall between the hall and the offices, with two 1 m doors.
    rect(&mut g, 258, 12, 262, 288, OCCUPIED);
    rect(&mut g, 258, 60, 262, 80, FREE);
    rect(&mut g, 258, 210, 262, 230, FREE);
    // Offices: lower and upper room, door at i 310..330.
    rect(&mut g, 262, 148, 388, 152, OCCUPIED);
    rect(&mut g, 310, 148, 330, 152, FREE);
    // Desks.
    for (i, j) in [(280, 30), (320, 30), (280, 100), (320, 100)] {
        rect(&mut g, i, j, i + 20, j + 12, OCCUPIED);
    }
    let disc = |g: &mut Vec<u8>, ci: f64, cj: f64, r: f64, v: u8| {
        for j in 0..H {
            for i in 0..W {
                let (dx, dy) = (i as f64 + 0.5 - ci, j as f64 + 0.5 - cj);
                if dx * dx + dy * dy <= r * r {
                    g[j * W + i] = v;
                }
            }
        }
    };
    // Chairs.
    for (i, j) in [(290.0, 48.0), (330.0, 48.0), (290.0, 92.0), (330.0, 92.0)] {
        disc(&mut g, i, j, 3.5, OCCUPIED);
    }
    // Upper room: a diagonal partition 3 cells thick, a round table.
    for t in 0..=200 {
        let s = t as f64 / 200.0;
        disc(&mut g, 285.0 + 45.0 * s, 175.0 + 45.0 * s, 1.6, OCCUPIED);
    }
    disc(&mut g, 355.0, 200.0, 10.0, OCCUPIED);
    // A closed closet in the upper right corner (free inside, no door).
    rect(&mut g, 345, 245, 388, 288, OCCUPIED);
    rect(&mut g, 349, 249, 384, 284, FREE);
    // An unscanned corner.
    rect(&mut g, 265, 255, 300, 288, UNKNOWN);
    // Hall: two rows of five racks (50 cm × 4.5 m), aisles of 1.6 m.
    for k in 0..5 {
        let i0 = 35 + 42 * k;
        rect(&mut g, i0, 40, i0 + 10, 130, OCCUPIED);
        rect(&mut g, i0, 160, i0 + 10, 250, OCCUPIED);
    }
    // Unscanned shadow behind the last rack.
    rect(&mut g, 213, 60, 218, 110, UNKNOWN);
    // Pillars between the rack rows and a hollow column with a free core.
    disc(&mut g, 98.0, 145.0, 4.0, OCCUPIED);
    disc(&mut g, 182.0, 145.0, 4.0, OCCUPIED);
    disc(&mut g, 236.0, 145.0, 7.0, OCCUPIED);
    disc(&mut g, 236.0, 145.0, 3.0, FREE);
    // Pallets and boxes where they leave 60 cm around them.
    let mut rng = Lcg(20_101);
    let mut placed = 0;
    while placed < 14 {
        let (w, h) = (4 + rng.next(6), 4 + rng.next(6));
        let (i0, j0) = (14 + rng.next(240 - w), 14 + rng.next(270 - h));
        let m = 12;
        let clear = (j0 - m..j0 + h + m)
            .all(|j| (i0.saturating_sub(m)..i0 + w + m).all(|i| g[j * W + i] == FREE));
        if clear {
            rect(&mut g, i0, j0, i0 + w, j0 + h, OCCUPIED);
            placed += 1;
        }
    }
    // Sensor speckles: single occupied cells in the hall.
    let mut speckles = 0;
    while speckles < 25 {
        let (i, j) = (14 + rng.next(240), 14 + rng.next(270));
        let clear = (j - 6..=j + 6).all(|jj| (i - 6..=i + 6).all(|ii| g[jj * W + ii] == FREE));
        if clear {
            g[j * W + i] = OCCUPIED;
            speckles += 1;
        }
    }
    g
}

/// The map as image pixels (row 0 at the top).
fn warehouse_pixels() -> Vec<u8> {
    let g = warehouse_cells();
    let mut px = Vec::with_capacity(W * H);
    for row in 0..H {
        let j = H - 1 - row;
        px.extend_from_slice(&g[j * W..(j + 1) * W]);
    }
    px
}

const WAREHOUSE_YAML: &str = "image: warehouse_map.pgm
resolution: 0.05
origin: [-2.0, -1.5, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
mode: trinary
";

fn write_pgm(path: &Path, w: usize, h: usize, px: &[u8]) {
    use image::ImageEncoder;
    use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
    let file = std::fs::File::create(path).expect("create the image");
    PnmEncoder::new(std::io::BufWriter::new(file))
        .with_subtype(PnmSubtype::Graymap(SampleEncoding::Binary))
        .write_image(px, w as u32, h as u32, image::ExtendedColorType::L8)
        .expect("write the image");
}

#[test]
#[ignore = "writes meshes/warehouse_map.{yaml,pgm}; run to regenerate them"]
fn write_warehouse_map() {
    write_pgm(
        &root().join("meshes/warehouse_map.pgm"),
        W,
        H,
        &warehouse_pixels(),
    );
    std::fs::write(warehouse_yaml(), WAREHOUSE_YAML).expect("write the yaml");
}

#[test]
fn the_committed_map_is_the_generated_one() {
    let img = image::open(root().join("meshes/warehouse_map.pgm"))
        .expect("meshes/warehouse_map.pgm decodes")
        .to_luma8();
    assert_eq!((img.width(), img.height()), (W as u32, H as u32));
    assert!(
        img.as_raw() == &warehouse_pixels(),
        "meshes/warehouse_map.pgm differs from the generator"
    );
    let yaml = std::fs::read_to_string(warehouse_yaml()).expect("yaml");
    assert_eq!(yaml, WAREHOUSE_YAML);
    // The map_server reading gives back the drawn cells.
    let map = OccupancyMap::load(warehouse_yaml()).expect("the map loads");
    let g = warehouse_cells();
    for j in 0..H {
        for i in 0..W {
            let want = match g[j * W + i] {
                FREE => Cell::Free,
                OCCUPIED => Cell::Occupied,
                _ => Cell::Unknown,
            };
            assert_eq!(map.cell(i, j), want, "cell ({i}, {j})");
        }
    }
    assert_eq!(map.origin(), [-2.0, -1.5, 0.0]);
    assert_eq!(map.resolution(), 0.05);
}

fn polygon(ring: &[[f64; 2]]) -> Polygon<f64> {
    Polygon::new(
        LineString::new(ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect()),
        vec![],
    )
}

/// Whether a cell's centre is at least `d` cells (Chebyshev) from every blocked cell.
fn deep(map: &OccupancyMap, i: usize, j: usize, d: usize, unknown: UnknownCells) -> bool {
    let (w, h) = (map.width(), map.height());
    (j.saturating_sub(d)..=(j + d).min(h - 1)).all(|jj| {
        (i.saturating_sub(d)..=(i + d).min(w - 1)).all(|ii| !map.is_blocked(ii, jj, unknown))
    }) && i >= d
        && j >= d
        && i + d < w
        && j + d < h
}

/// The robot's free space traced on the warehouse map: every point of the polygons' edges
/// and of the region they bound keeps the radius from every blocked cell (exactly: the grid
/// was cleared with the margin), and every free cell a few cells deeper than the radius and
/// the margin, connected to the goal through such cells, is in it.
fn check_polygons(map: &OccupancyMap, unknown: UnknownCells) {
    let radius = 0.2;
    let opts = MapOptions {
        unknown,
        ..MapOptions::default()
    };
    let polys = map.polygons(GOAL, radius, &opts).expect("traces");
    let ws = polygon(&polys.workspace);
    let holes: Vec<Polygon<f64>> = polys.obstacles.iter().map(|r| polygon(r)).collect();
    let free_space = |p: [f64; 2]| {
        let c = Coord { x: p[0], y: p[1] };
        ws.contains(&c) && !holes.iter().any(|h| h.contains(&c))
    };
    for ring in std::iter::once(&polys.workspace).chain(&polys.obstacles) {
        let mut closed = ring.clone();
        closed.push(ring[0]);
        let c = clearance(map, &closed, radius, unknown);
        assert!(c >= radius - 1e-9, "a ring comes {c} from a blocked cell");
    }
    let (w, h) = (map.width(), map.height());
    let mut inside = 0;
    for j in 0..h {
        for i in 0..w {
            let c = map.cell_center(i, j);
            if free_space(c) {
                inside += 1;
                let d = clearance(map, &[c, c], radius, unknown);
                assert!(
                    d >= radius - 1e-9,
                    "({i}, {j}) at {c:?} is {d} from a blocked cell"
                );
            }
        }
    }
    // Completeness: free cells deeper than the radius, the margin and two cells of
    // quantisation and simplification are inside.
    let d = ((radius + polys.margin) / map.resolution()).ceil() as usize + 2;
    let (gi, gj) = map.cell_at(GOAL).expect("goal on the map");
    assert!(deep(map, gi, gj, d, unknown));
    let mut seen = vec![false; w * h];
    let mut stack = vec![(gi, gj)];
    seen[gj * w + gi] = true;
    let mut checked = 0;
    while let Some((i, j)) = stack.pop() {
        let c = map.cell_center(i, j);
        assert!(
            free_space(c),
            "deep free cell ({i}, {j}) at {c:?} is not in free space"
        );
        checked += 1;
        for (di, dj) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (ni, nj) = (i as isize + di, j as isize + dj);
            if ni < 0 || nj < 0 || ni as usize >= w || nj as usize >= h {
                continue;
            }
            let (ni, nj) = (ni as usize, nj as usize);
            if !seen[nj * w + ni] && deep(map, ni, nj, d, unknown) {
                seen[nj * w + ni] = true;
                stack.push((ni, nj));
            }
        }
    }
    assert!(checked > 20_000, "only {checked} deep free cells reached");
    // Simplification keeps the polygons small: long walls are single edges.
    let vertices: usize =
        polys.workspace.len() + polys.obstacles.iter().map(Vec::len).sum::<usize>();
    println!(
        "{unknown:?}: {} obstacles, {vertices} vertices, {inside} cell centres inside, {checked} deep cells checked, margin {}",
        polys.obstacles.len(),
        polys.margin
    );
    assert!(vertices < 3000, "{vertices} vertices");
    // A cell for the simplification, a quarter for the contour, 10⁻⁶ for the jitter.
    assert!(polys.margin <= (1.25 + 1e-6) * map.resolution() + 1e-12);
}

#[test]
fn polygons_keep_the_radius_and_hold_the_deep_free_cells() {
    let map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    check_polygons(&map, UnknownCells::Obstacle);
    check_polygons(&map, UnknownCells::Free);
}

/// Distance from a world point to the square of cell (i, j).
fn distance_to_cell(map: &OccupancyMap, p: [f64; 2], i: usize, j: usize) -> f64 {
    let g = map.world_to_grid(p);
    let dx = (i as f64 - g[0]).max(g[0] - (i as f64 + 1.0)).max(0.0);
    let dy = (j as f64 - g[1]).max(g[1] - (j as f64 + 1.0)).max(0.0);
    dx.hypot(dy) * map.resolution()
}

/// Samples every segment of `points` at quarter-cell spacing; returns the smallest distance to
/// a blocked cell's square (0 inside one), unknown cells blocked.
/// Why the system of `planner`'s mesh (walls φ = 1, goal φ = 0, as a map planner solves it)
/// is not an M-matrix, if it is not: the traced mesher keeps its bridges' midpoints
/// unrefined (`Bridges::Midpoints`), which may leave obtuse angles facing wall edges, and
/// that is harmless only because the walls are Dirichlet.
fn not_m_matrix(planner: &Planner) -> Option<String> {
    let bcs = BoundaryConditions::default();
    let mesh = std::sync::Arc::new(planner.mesh().clone());
    let assembler = Assembler::new(mesh, &bcs, AssemblyOptions::default()).expect("assembler");
    let system = assembler.assemble(&bcs).expect("system");
    system.not_m_matrix().map(|r| format!("{r:?}"))
}

fn path_clearance(map: &OccupancyMap, points: &[[f64; 2]], radius: f64) -> f64 {
    clearance(map, points, radius, UnknownCells::Obstacle)
}

/// [`path_clearance`] with unknown cells as `unknown` says (cells past the map's edge count
/// as blocked).
fn clearance(map: &OccupancyMap, points: &[[f64; 2]], radius: f64, unknown: UnknownCells) -> f64 {
    let res = map.resolution();
    let reach = (radius / res).ceil() as isize + 3;
    let mut min = f64::INFINITY;
    for seg in points.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = (len / (0.25 * res)).ceil().max(1.0) as usize;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let g = map.world_to_grid(p);
            let (ci, cj) = (g[0].floor() as isize, g[1].floor() as isize);
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let (i, j) = (ci + di, cj + dj);
                    let off =
                        i < 0 || j < 0 || i as usize >= map.width() || j as usize >= map.height();
                    if off {
                        // Past the edge: the distance to the grid's outside.
                        let dx = (-g[0]).max(g[0] - map.width() as f64).max(0.0);
                        let dy = (-g[1]).max(g[1] - map.height() as f64).max(0.0);
                        let inside = dx == 0.0 && dy == 0.0;
                        let edge = g[0]
                            .min(g[1])
                            .min(map.width() as f64 - g[0])
                            .min(map.height() as f64 - g[1]);
                        min = min.min(if inside { edge * res } else { 0.0 });
                        continue;
                    }
                    if map.is_blocked(i as usize, j as usize, unknown) {
                        min = min.min(distance_to_cell(map, p, i as usize, j as usize));
                    }
                }
            }
        }
    }
    min
}

#[test]
fn paths_on_the_warehouse_map_reach_the_goal_and_keep_the_radius() {
    let radius = 0.2;
    let t = Instant::now();
    let map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let planner = map
        .planner(
            GOAL,
            radius,
            &MapOptions::default(),
            &PlannerOptions::default(),
        )
        .expect("planner");
    let plan_ms = t.elapsed().as_secs_f64() * 1e3;
    let starts: Vec<[f64; 2]> = REACHABLE.iter().chain(&UNREACHABLE).copied().collect();
    let report = planner.plan_report(&starts);
    println!(
        "load {load_ms:.1} ms, planner {plan_ms:.1} ms, timings {:?}, mesh {} vertices / {} triangles",
        report.timings_ms, report.mesh.vertices, report.mesh.triangles
    );
    assert_eq!(report.potential.interior_local_minima, 0);
    for path in &report.paths {
        let reachable = REACHABLE.contains(&path.start);
        println!(
            "{:?}: {} length {:.2} clearance {:.3}",
            path.start, path.status, path.length, path.min_clearance
        );
        if !reachable {
            assert_ne!(path.status.as_str(), "reached_goal", "{:?}", path.start);
            continue;
        }
        assert_eq!(path.status.as_str(), "reached_goal", "{:?}", path.start);
        let clearance = path_clearance(&map, &path.points, radius);
        assert!(
            clearance >= radius - 1e-9,
            "path from {:?} comes {clearance} from an occupied or unknown cell",
            path.start
        );
    }
}

/// A changed region is a new first plan on the same map: a block put down on the path makes
/// the new path go round it at the radius (checked on the changed grid), clearing it again
/// gives back the polygons of the untouched map, and a region off the map is refused.
#[test]
fn a_changed_region_replans_round_it() {
    let radius = 0.2;
    let opts = (MapOptions::default(), PlannerOptions::default());
    let mut map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    let before = map.polygons(GOAL, radius, &opts.0).expect("polygons");
    let start = REACHABLE[0];
    let first = map
        .planner(GOAL, radius, &opts.0, &opts.1)
        .expect("planner")
        .plan(start);
    assert!(first.status.reached_goal(), "{}", first.status);
    // A 0.5 m square block centred on the middle of the first path.
    let mid = first.points[first.points.len() / 2];
    let (ci, cj) = map.cell_at(mid).expect("on the map");
    let (columns, rows) = (ci - 5..ci + 5, cj - 5..cj + 5);
    map.set_region(columns.clone(), rows.clone(), Cell::Occupied)
        .expect("on the map");
    for (i, j) in [(ci - 5, cj - 5), (ci + 4, cj + 4)] {
        assert_eq!(map.cell(i, j), Cell::Occupied);
    }
    assert!(
        path_clearance(&map, &first.points, radius) < radius,
        "the block does not touch the first path"
    );
    let second = map
        .planner(GOAL, radius, &opts.0, &opts.1)
        .expect("planner")
        .plan(start);
    assert!(second.status.reached_goal(), "{}", second.status);
    let clearance = path_clearance(&map, &second.points, radius);
    assert!(
        clearance >= radius - 1e-9,
        "the new path comes {clearance} from a blocked cell"
    );
    assert!(
        second.length > first.length,
        "{} vs {}",
        second.length,
        first.length
    );

    map.set_region(columns, rows, Cell::Free)
        .expect("on the map");
    let after = map.polygons(GOAL, radius, &opts.0).expect("polygons");
    assert_eq!(after.workspace, before.workspace);
    assert_eq!(after.obstacles, before.obstacles);

    let (w, h) = (map.width(), map.height());
    let corner = map.cell(w - 2, 0);
    let err = map
        .set_region(w - 2..w + 1, 0..1, Cell::Occupied)
        .expect_err("past the edge")
        .to_string();
    assert!(
        err.contains(&format!("columns {}..{}", w - 2, w + 1)),
        "{err}"
    );
    assert!(
        err.contains(&format!("columns 0..{w}, rows 0..{h}")),
        "{err}"
    );
    assert_eq!(
        map.cell(w - 2, 0),
        corner,
        "a refused region changes nothing"
    );
}

/// A scratch folder for map files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hplan-map-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn load_err(dir: &Path, yaml: &str) -> String {
    let path = dir.join("m.yaml");
    std::fs::write(&path, yaml).expect("write");
    OccupancyMap::load(&path)
        .expect_err("must be rejected")
        .to_string()
}

#[test]
fn bad_maps_are_named() {
    let dir = scratch("bad");
    // A 4 × 3 image: top row occupied, one unknown, the rest free.
    let px = [
        0, 0, 0, 0, //
        254, 205, 254, 254, //
        254, 254, 254, 254,
    ];
    write_pgm(&dir.join("m.pgm"), 4, 3, &px);
    let ok = "image: m.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\n";
    let e = load_err(
        &dir,
        "image: missing.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n",
    );
    assert!(
        e.contains("missing.pgm") && e.contains("field `image`"),
        "{e}"
    );
    let e = load_err(&dir, "resolution: 0.1\norigin: [0, 0, 0]\n");
    assert!(e.contains("missing field `image`"), "{e}");
    let e = load_err(&dir, "image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n");
    assert!(e.contains("`resolution`") && e.contains("positive"), "{e}");
    let e = load_err(&dir, "image: m.pgm\nresolution: abc\norigin: [0, 0, 0]\n");
    assert!(e.contains("`resolution`"), "{e}");
    let e = load_err(&dir, "image: m.pgm\nresolution: 0.1\norigin: [0, 0]\nx\n");
    assert!(e.contains("YAML"), "{e}");
    let e = load_err(&dir, "image: m.pgm\nresolution: 0.1\norigin: 3\n");
    assert!(e.contains("`origin`"), "{e}");
    let e = load_err(&dir, &format!("{ok}mode: fancy\n"));
    assert!(e.contains("unsupported mode `fancy`"), "{e}");
    let e = load_err(&dir, &format!("{ok}negate: 2\n"));
    assert!(e.contains("`negate`"), "{e}");
    let e = load_err(&dir, &format!("{ok}occupied_thresh: 1.5\n"));
    assert!(e.contains("`occupied_thresh`"), "{e}");
    std::fs::write(dir.join("junk.pgm"), b"not an image").expect("write");
    let e = load_err(
        &dir,
        "image: junk.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n",
    );
    assert!(e.contains("junk.pgm") && e.contains("decode"), "{e}");

    // The good header: cells are read bottom-up, the frame is the origin's.
    std::fs::write(dir.join("m.yaml"), ok).expect("write");
    let map = OccupancyMap::load(dir.join("m.yaml")).expect("loads");
    assert_eq!((map.width(), map.height()), (4, 3));
    assert_eq!(map.cell(0, 2), Cell::Occupied);
    assert_eq!(map.cell(1, 1), Cell::Unknown);
    assert_eq!(map.cell(1, 0), Cell::Free);
    assert_eq!(map.cell_center(1, 0), [1.75, 2.25]);
    assert_eq!(map.cell_at([1.75, 3.25]), Some((1, 2)));
    let opts = MapOptions::default();
    let err = |goal: [f64; 2]| {
        map.to_scene(goal, 0.0, &opts)
            .expect_err("must be rejected")
            .to_string()
    };
    assert!(err([1.75, 3.25]).contains("occupied cell (column 1, row 2"));
    assert!(err([1.75, 2.75]).contains("an unknown cell"));
    assert!(err([0.0, 0.0]).contains("outside the map"));
    assert!(err([f64::NAN, 2.5]).contains("outside the map"));
    // Too near the edge for the tracing margin.
    assert!(
        err([1.25, 2.25]).contains("closer than the robot radius 0 plus the tracing margin"),
        "{}",
        err([1.25, 2.25])
    );
    assert!(matches!(
        map.to_scene([1.25, 2.25], -1.0, &opts),
        Err(MapError::BadRadius(_))
    ));

    // A grid past the size limit is refused before anything is allocated for it.
    let huge = OccupancyMap::from_cells(1 << 15, 1 << 14, 0.05, [0.0, 0.0, 0.0], Vec::new())
        .expect_err("too large");
    assert!(
        huge.to_string().contains("the most a map may have"),
        "{huge}"
    );

    // An all-occupied map is empty.
    write_pgm(&dir.join("full.pgm"), 2, 2, &[0, 0, 0, 0]);
    std::fs::write(
        dir.join("full.yaml"),
        "image: full.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n",
    )
    .expect("write");
    let full = OccupancyMap::load(dir.join("full.yaml")).expect("loads");
    let e = full.to_scene([0.05, 0.05], 0.0, &opts).expect_err("empty");
    assert!(matches!(e, MapError::EmptyMap { .. }), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn modes_negate_and_png() {
    let dir = scratch("modes");
    // Grey levels 0, 100, 205, 254 in one row, as a PNG.
    image::GrayImage::from_raw(4, 1, vec![0, 100, 205, 254])
        .expect("image")
        .save(dir.join("m.png"))
        .expect("png");
    let load = |extra: &str| {
        std::fs::write(
            dir.join("m.yaml"),
            format!("image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\n{extra}"),
        )
        .expect("write");
        OccupancyMap::load(dir.join("m.yaml")).expect("loads")
    };
    let cells = |extra: &str| {
        let map = load(extra);
        (0..4).map(|i| map.cell(i, 0)).collect::<Vec<_>>()
    };
    use Cell::{Free, Occupied, Unknown};
    // Occupancy (255 - v) / 255: 1.0, 0.61, 0.196.., 0.004.
    assert_eq!(cells(""), [Occupied, Unknown, Unknown, Free]);
    // Scale: between the thresholds a free cell with a graded cost, 1 at the free threshold
    // rising to 252 at the occupied one (0.608 of the way from 0.196 to 0.65: cost 229).
    assert_eq!(cells("mode: scale\n"), [Occupied, Free, Free, Free]);
    let scale = load("mode: scale\n");
    assert_eq!(
        (0..4).map(|i| scale.cost(i, 0)).collect::<Vec<_>>(),
        [0, 229, 1, 0]
    );
    assert_eq!(load("").cost(1, 0), 0, "trinary maps have no costs");
    // Negated: v / 255.
    assert_eq!(cells("negate: 1\n"), [Free, Unknown, Occupied, Occupied]);
    // Raw: percent, above 100 unknown.
    assert_eq!(cells("mode: raw\n"), [Free, Occupied, Unknown, Unknown]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_rotated_map_traces_in_its_frame() {
    // A 24 × 16 free room with one occupied block, rotated by 90° about (5, 1).
    let (w, h) = (24, 16);
    let mut cells = vec![Cell::Free; w * h];
    for j in 6..8 {
        for i in 10..12 {
            cells[j * w + i] = Cell::Occupied;
        }
    }
    let yaw = std::f64::consts::FRAC_PI_2;
    let map = OccupancyMap::from_cells(w, h, 0.25, [5.0, 1.0, yaw], cells).expect("map");
    // Cell (0, 0)'s centre is an eighth of a metre along the rotated x (world +y) and y
    // (world −x).
    let c = map.cell_center(0, 0);
    assert!(
        (c[0] - 4.875).abs() < 1e-12 && (c[1] - 1.125).abs() < 1e-12,
        "{c:?}"
    );
    let goal = map.cell_center(3, 3);
    let polys = map
        .polygons(goal, 0.0, &MapOptions::default())
        .expect("traces");
    assert_eq!(polys.obstacles.len(), 1);
    let hole = polygon(&polys.obstacles[0]);
    for (i, j) in [(10, 6), (11, 7)] {
        let p = map.cell_center(i, j);
        assert!(hole.contains(&Coord { x: p[0], y: p[1] }), "({i}, {j})");
    }
    let scene = map
        .to_scene(goal, 0.1, &MapOptions::default())
        .expect("scene");
    let planner = Planner::new(&scene).expect("planner");
    let path = planner.plan(map.cell_center(20, 12));
    assert_eq!(path.status.as_str(), "reached_goal");
    assert!(path_clearance(&map, &path.points, 0.1) >= 0.1 - 1e-9);
}

/// A coarser simplification has fewer vertices and a wider margin, and its paths keep the
/// radius from every blocked cell all the same; a start that keeps the radius but that the
/// wider margin leaves outside the polygons is led in over the clear cells.
#[test]
fn a_coarser_simplification_keeps_the_clearance_through_its_margin() {
    let radius = 0.2;
    let map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    let opts = |simplify_cells| MapOptions {
        simplify_cells,
        ..MapOptions::default()
    };
    let fine = map.polygons(GOAL, radius, &opts(0.5)).expect("traces");
    let coarse = map.polygons(GOAL, radius, &opts(2.0)).expect("traces");
    let count = |p: &harmonic_planner::map::MapPolygons| {
        p.workspace.len() + p.obstacles.iter().map(Vec::len).sum::<usize>()
    };
    assert!(
        count(&coarse) < count(&fine),
        "{} vs {}",
        count(&coarse),
        count(&fine)
    );
    let res = map.resolution();
    assert!((coarse.margin - (2.25 + 1e-6) * res).abs() < 1e-12);
    assert!((fine.margin - (0.75 + 1e-6) * res).abs() < 1e-12);
    let planner = map
        .planner(GOAL, radius, &opts(2.0), &PlannerOptions::default())
        .expect("planner");
    for start in REACHABLE {
        let path = planner.plan(start);
        assert_eq!(path.status.as_str(), "reached_goal", "{start:?}");
        let clearance = path_clearance(&map, &path.points, radius);
        assert!(clearance >= radius - 1e-9, "{start:?}: {clearance}");
    }
    // A start two cells off a wall of the lower office room: clear for the radius, outside
    // the coarse polygons.
    let scene_planner =
        Planner::new(&map.to_scene(GOAL, radius, &opts(2.0)).expect("scene")).expect("planner");
    let (gi, gj) = map.cell_at(GOAL).expect("on the map");
    let near_wall = (0..gi)
        .rev()
        .map(|i| (i, gj))
        .find(|&(i, j)| {
            let c = map.cell_center(i, j);
            let d = clearance(&map, &[c, c], radius, UnknownCells::Obstacle);
            d >= radius + res && d < radius + 2.0 * res
        })
        .map(|(i, j)| map.cell_center(i, j))
        .expect("a cell just clear of the wall");
    assert_eq!(
        scene_planner.plan(near_wall).status.as_str(),
        "outside_workspace",
        "{near_wall:?} is outside the coarse polygons"
    );
    let path = planner.plan(near_wall);
    assert_eq!(path.status.as_str(), "reached_goal", "{near_wall:?}");
    assert_eq!(path.points[0], near_wall);
    assert!(path_clearance(&map, &path.points, radius) >= radius - 1e-9);
}

/// Nav2's own maps with NavFn's start/goal pairs (when the maps are at hand): every first plan
/// reaches the goal and keeps the robot's radius from every occupied and unknown cell.
#[test]
fn nav2_maps_plans_reach_and_keep_the_radius_on_the_grid() {
    let Some(dir) = harmonic_fixtures::nav2_maps_dir() else {
        eprintln!("skipped: set HARMONIC_NAV2_MAPS to a folder of Nav2's maps");
        return;
    };
    let radius = harmonic_fixtures::NAVFN_ROBOT_RADIUS;
    for r in harmonic_fixtures::NAVFN_REQUESTS {
        let map = OccupancyMap::load(dir.join(format!("{}.yaml", r.map))).expect("loads");
        for mesher in [MapMesher::Quadtree, MapMesher::Traced] {
            let opts = MapOptions {
                mesher,
                ..MapOptions::default()
            };
            let planner = map
                .planner(r.goal, radius, &opts, &PlannerOptions::default())
                .expect("planner");
            let path = planner.plan(r.start);
            let what = format!("{} from {:?} ({mesher:?})", r.map, r.start);
            assert_eq!(path.status.as_str(), "reached_goal", "{what}");
            // No step of nothing (a lead-in from a start on a cell centre to that centre).
            let shortest = path
                .points
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .fold(f64::INFINITY, f64::min);
            assert!(shortest > 1e-9, "{what}: a step of {shortest}");
            let clearance = path_clearance(&map, &path.points, radius);
            // Both meshers keep the radius exactly: the clear cells are found on the grid.
            assert!(
                clearance >= radius - 1e-9,
                "{what}: {clearance} from a blocked cell"
            );
            assert_eq!(
                planner
                    .plan_report(&[r.start])
                    .potential
                    .interior_local_minima,
                0,
                "{what}"
            );
            assert_eq!(not_m_matrix(&planner), None, "{what}");
        }
    }
}

/// The quadtree planner on the bundled warehouse: the mesh is the robot's clear cells (the
/// right isosceles triangles give an M-matrix, so no interior minimum), paths reach, and
/// every point of them keeps the radius from every blocked cell exactly; the closet and the
/// patch outside stay unreachable. Snapped to blocks of 2 cells, fewer triangles, and a
/// start on a clear cell the blocks left out is led in over clear cells.
#[test]
fn quadtree_paths_on_the_warehouse_keep_the_radius_exactly() {
    let radius = 0.2;
    let map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    let quadtree = |snap| MapOptions {
        mesher: MapMesher::Quadtree,
        snap,
        ..MapOptions::default()
    };
    let plain = map
        .planner(
            GOAL,
            radius,
            &quadtree(Snap::Off),
            &PlannerOptions::default(),
        )
        .expect("planner");
    let starts: Vec<[f64; 2]> = REACHABLE.iter().chain(&UNREACHABLE).copied().collect();
    let report = plain.plan_report(&starts);
    assert_eq!(report.potential.interior_local_minima, 0);
    let quality = plain.mesh().quality();
    assert!(quality.max_angle_deg <= 90.0 + 1e-9, "{quality:?}");
    for path in &report.paths {
        if UNREACHABLE.contains(&path.start) {
            assert_ne!(path.status.as_str(), "reached_goal", "{:?}", path.start);
            continue;
        }
        assert_eq!(path.status.as_str(), "reached_goal", "{:?}", path.start);
        let clearance = path_clearance(&map, &path.points, radius);
        assert!(clearance >= radius - 1e-9, "{:?}: {clearance}", path.start);
    }

    let snapped = map
        .planner(
            GOAL,
            radius,
            &quadtree(Snap::Blocks(2)),
            &PlannerOptions::default(),
        )
        .expect("planner");
    let (fine, coarse) = (
        plain.mesh().triangles().len(),
        snapped.mesh().triangles().len(),
    );
    assert!(coarse < fine, "{coarse} triangles snapped, {fine} not");
    // A point on a clear cell (every point of it at least the radius from every blocked
    // cell) that the snapped mesh leaves out.
    let res = map.resolution();
    let clear = |i: usize, j: usize| {
        let c = map.cell_center(i, j);
        let reach = (radius / res).ceil() as usize + 2;
        (j.saturating_sub(reach)..(j + reach + 1).min(map.height())).all(|jj| {
            (i.saturating_sub(reach)..(i + reach + 1).min(map.width())).all(|ii| {
                !map.is_blocked(ii, jj, UnknownCells::Obstacle)
                    || distance_to_cell(&map, c, ii, jj) >= radius + res / 2f64.sqrt()
            })
        }) && i > reach
            && j > reach
            && i + reach < map.width()
            && j + reach < map.height()
    };
    let outside = (0..map.height())
        .flat_map(|j| (0..map.width()).map(move |i| (i, j)))
        .find(|&(i, j)| {
            clear(i, j)
                && snapped
                    .mesh()
                    .locate(map.cell_center(i, j).into(), None)
                    .is_none()
                && plain
                    .mesh()
                    .locate(map.cell_center(i, j).into(), None)
                    .is_some()
        })
        .map(|(i, j)| map.cell_center(i, j))
        .expect("a clear cell beside the snapped mesh");
    let path = snapped.plan(outside);
    assert_eq!(path.status.as_str(), "reached_goal", "{outside:?}");
    assert_eq!(path.points[0], outside);
    let clearance = path_clearance(&map, &path.points, radius);
    assert!(clearance >= radius - 1e-9, "{outside:?}: {clearance}");
}

/// Bad quadtree input gets one line: a goal too near a wall for the radius, a block size
/// that is no power of two.
#[test]
fn quadtree_errors_name_the_problem() {
    let map = OccupancyMap::load(warehouse_yaml()).expect("loads");
    let opts = MapOptions {
        mesher: MapMesher::Quadtree,
        ..MapOptions::default()
    };
    let near_wall = map
        .planner(GOAL, 2.0, &opts, &PlannerOptions::default())
        .expect_err("too close");
    assert!(
        matches!(near_wall, MapError::GoalTooClose { .. }),
        "{near_wall}"
    );
    assert!(
        near_wall.to_string().contains("robot radius 2"),
        "{near_wall}"
    );
    let bad = MapOptions {
        snap: Snap::Blocks(3),
        ..opts
    };
    let e = map
        .planner(GOAL, 0.2, &bad, &PlannerOptions::default())
        .expect_err("3 is no power of two");
    assert!(e.to_string().contains("snap"), "{e}");
}

/// A random occupancy grid of `w × h` cells: rectangles and discs of occupied and unknown
/// cells, and speckles.
fn random_cells(seed: u64, w: usize, h: usize) -> Vec<Cell> {
    let mut rng = Lcg(seed);
    let mut cells = vec![Cell::Free; w * h];
    let kind = |rng: &mut Lcg| {
        if rng.next(4) == 0 {
            Cell::Unknown
        } else {
            Cell::Occupied
        }
    };
    for _ in 0..rng.next(12) {
        let (i0, j0) = (rng.next(w), rng.next(h));
        let (dw, dh) = (1 + rng.next(w / 4), 1 + rng.next(h / 4));
        let c = kind(&mut rng);
        for j in j0..(j0 + dh).min(h) {
            for i in i0..(i0 + dw).min(w) {
                cells[j * w + i] = c;
            }
        }
    }
    for _ in 0..rng.next(6) {
        let (ci, cj, r) = (
            rng.next(w) as f64,
            rng.next(h) as f64,
            1.0 + rng.next(6) as f64,
        );
        let c = kind(&mut rng);
        for j in 0..h {
            for i in 0..w {
                if (i as f64 - ci).hypot(j as f64 - cj) <= r {
                    cells[j * w + i] = c;
                }
            }
        }
    }
    for _ in 0..rng.next(20) {
        cells[rng.next(w * h)] = kind(&mut rng);
    }
    cells
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// Random maps, radii and tolerances: the traced planner is built or refused with one of
    /// the goal's errors (never a failure of the rings it traced), its polygons keep the
    /// radius from every blocked cell, the potential has no interior minimum, and every path
    /// that reaches the goal keeps the radius, exactly, checked on the grid.
    #[test]
    fn random_maps_plan_within_the_radius(
        seed in proptest::prelude::any::<u64>(),
        radius_cells in 0.0f64..5.0,
        simplify_cells in 0.0f64..2.5,
    ) {
        let (w, h, res) = (60, 45, 0.1);
        let map = OccupancyMap::from_cells(w, h, res, [-1.0, 2.0, 0.3], random_cells(seed, w, h))
            .expect("map");
        let radius = radius_cells * res;
        let opts = MapOptions { simplify_cells, mesher: MapMesher::Traced, ..MapOptions::default() };
        let mut rng = Lcg(seed ^ 0x9e37_79b9);
        let free: Vec<(usize, usize)> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .filter(|&(i, j)| map.cell(i, j) == Cell::Free)
            .collect();
        proptest::prop_assume!(!free.is_empty());
        // A goal with some room around it, mostly (a few tries, then any free cell).
        let room = radius_cells.ceil() as usize + 3;
        let mut pick = free[rng.next(free.len())];
        for _ in 0..8 {
            if deep(&map, pick.0, pick.1, room, UnknownCells::Obstacle) {
                break;
            }
            pick = free[rng.next(free.len())];
        }
        let (gi, gj) = pick;
        let goal = map.cell_center(gi, gj);
        match map.planner(goal, radius, &opts, &PlannerOptions::default()) {
            Err(e) => proptest::prop_assert!(
                matches!(e, MapError::GoalTooClose { .. }),
                "unexpected refusal: {e}"
            ),
            Ok(planner) => {
                let polys = map.polygons(goal, radius, &opts).expect("traced");
                for ring in std::iter::once(&polys.workspace).chain(&polys.obstacles) {
                    let mut closed = ring.clone();
                    closed.push(ring[0]);
                    let c = clearance(&map, &closed, radius, UnknownCells::Obstacle);
                    proptest::prop_assert!(c >= radius - 1e-9, "a ring comes {c} from a blocked cell");
                }
                let starts: Vec<[f64; 2]> = (0..4)
                    .map(|_| {
                        let (i, j) = free[rng.next(free.len())];
                        map.cell_center(i, j)
                    })
                    .collect();
                let report = planner.plan_report(&starts);
                proptest::prop_assert_eq!(report.potential.interior_local_minima, 0);
                proptest::prop_assert_eq!(not_m_matrix(&planner), None);
                for path in &report.paths {
                    if path.status.as_str() == "reached_goal" {
                        let c = path_clearance(&map, &path.points, radius);
                        proptest::prop_assert!(
                            c >= radius - 1e-9,
                            "path from {:?} comes {} from a blocked cell",
                            path.start,
                            c
                        );
                    }
                }
            }
        }
    }
}

/// The `map` fuzz target's own code, so CI replays its corpus as the fuzzer ran it.
#[path = "../fuzz/src/map.rs"]
mod fuzz_map;

/// CI replays the `map` fuzz corpus (seeds, and what the fuzzer found, kept as regressions):
/// no input may panic, and the seed maps plan.
#[test]
fn the_map_fuzz_corpus_replays_without_a_panic() {
    let files = harmonic_fixtures::fuzz_corpus("map");
    assert!(files.len() >= 7, "seed corpus present: {}", files.len());
    let (outcomes, panicked) = harmonic_fixtures::replay(&files, fuzz_map::run_map);
    assert!(panicked.is_empty(), "panicked:\n{}", panicked.join("\n"));
    let reached: usize = outcomes
        .iter()
        .map(|o| match o {
            fuzz_map::MapOutcome::Planned(_, r) => *r,
            _ => 0,
        })
        .sum();
    assert!(reached >= 10, "the seed maps plan: {reached} paths reached");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// `set_region` on a random map gives the map built from the changed cells: the same
    /// cells, and the same traced polygons (which read the map's bit grids, not its cells);
    /// a region past the edge is refused and changes nothing.
    #[test]
    fn set_region_is_the_map_of_the_changed_cells(
        seed in proptest::prelude::any::<u64>(),
        (w, h) in (4usize..150, 4usize..40),
        region in (0usize..160, 0usize..160, 0usize..50, 0usize..50),
        kind in 0usize..3,
    ) {
        let cell = [Cell::Free, Cell::Occupied, Cell::Unknown][kind];
        let cells = random_cells(seed, w, h);
        let mut map = OccupancyMap::from_cells(w, h, 0.05, [0.0; 3], cells.clone()).unwrap();
        let (i0, i1) = (region.0.min(region.1), region.0.max(region.1));
        let (j0, j1) = (region.2.min(region.3), region.2.max(region.3));
        let fits = i1 <= w && j1 <= h;
        let result = map.set_region(i0..i1, j0..j1, cell);
        proptest::prop_assert_eq!(result.is_ok(), fits);
        let mut expected = cells;
        if fits {
            for j in j0..j1 {
                for i in i0..i1 {
                    expected[j * w + i] = cell;
                }
            }
        }
        let rebuilt = OccupancyMap::from_cells(w, h, 0.05, [0.0; 3], expected).unwrap();
        for j in 0..h {
            for i in 0..w {
                proptest::prop_assert_eq!(map.cell(i, j), rebuilt.cell(i, j));
            }
        }
        let goal = rebuilt.cell_center(w / 2, h / 2);
        let (a, b) = (
            map.polygons(goal, 0.05, &MapOptions::default()),
            rebuilt.polygons(goal, 0.05, &MapOptions::default()),
        );
        proptest::prop_assert_eq!(format!("{a:?}"), format!("{b:?}"));
    }
}

/// A pillar five cells off a wall, a robot of one cell's radius: the default tracing margin
/// (1¼ cells) closes the three clear rows of that gap, and with them a loop of the free
/// space, but a quarter-cell margin (no simplification) keeps the middle row. `auto` then
/// meshes the unsimplified traced rings (fewer triangles than the quadtree), and starts in
/// the gap, on its outer clear rows included, reach the goal keeping the radius.
#[test]
fn auto_traces_unsimplified_where_the_default_margin_closes_a_loop() {
    let (w, h, res, radius) = (30, 20, 0.1, 0.1);
    let cells: Vec<Cell> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let wall = i == 0 || j == 0 || i == w - 1 || j == h - 1;
            let pillar = (10..20).contains(&i) && (6..12).contains(&j);
            if wall || pillar {
                Cell::Occupied
            } else {
                Cell::Free
            }
        })
        .collect();
    let map = OccupancyMap::from_cells(w, h, res, [0.0, 0.0, 0.0], cells).expect("map");
    let goal = map.cell_center(25, 15);
    let with = |mesher, simplify_cells| {
        let opts = MapOptions {
            mesher,
            simplify_cells,
            ..MapOptions::default()
        };
        map.planner(goal, radius, &opts, &PlannerOptions::default())
            .expect("planner")
    };
    let triangles = |p: &Planner| p.mesh().triangles().len();
    let auto = with(MapMesher::Auto, 1.0);
    let unsimplified = with(MapMesher::Traced, 0.0);
    let quadtree = with(MapMesher::Quadtree, 1.0);
    assert_eq!(triangles(&auto), triangles(&unsimplified));
    assert!(
        triangles(&auto) < triangles(&quadtree),
        "{} vs {}",
        triangles(&auto),
        triangles(&quadtree)
    );
    // The default margin closes the gap: the scene traced at the default simplification
    // leaves its middle row out.
    let scene = map
        .to_scene(goal, radius, &MapOptions::default())
        .expect("scene");
    let gap = map.cell_center(15, 3);
    assert_eq!(
        Planner::new(&scene)
            .expect("planner")
            .plan(gap)
            .status
            .as_str(),
        "outside_workspace"
    );
    for (i, j) in [(15, 3), (15, 2), (15, 4), (11, 2), (3, 3)] {
        let start = map.cell_center(i, j);
        let path = auto.plan(start);
        assert_eq!(path.status.as_str(), "reached_goal", "from cell ({i}, {j})");
        let clearance = path_clearance(&map, &path.points, radius);
        assert!(clearance >= radius - 1e-9, "({i}, {j}): {clearance}");
        let end = path.points.last().expect("a point");
        assert!((end[0] - goal[0]).hypot(end[1] - goal[1]) < 1e-9);
    }
}

/// A small arena in a large map of unknown cells, as SLAM leaves them, is planned on the part
/// of the map that holds it: the same statuses and paths (to 1e-9) as on the whole map (whose
/// planner is made here by opening one enclosed cell at a far corner, which keeps the part
/// from being cut; the map is rotated, so the part's cells must be placed as the map's).
/// Starts on the unknown cells outside the part are `start_in_obstacle`, starts off the map
/// `outside_workspace`, and a goal there is refused naming the map's own cell.
#[test]
fn a_small_arena_in_a_large_unknown_map_plans_as_the_whole_map() {
    let (w, h, res, radius) = (400, 300, 0.05, 0.1);
    let arena = |i: usize, j: usize| -> Option<Cell> {
        let (x, y) = (i.checked_sub(150)?, j.checked_sub(90)?);
        if x >= 60 || y >= 50 {
            return None;
        }
        let wall = x == 0 || y == 0 || x == 59 || y == 49;
        let pillar = (20..24).contains(&x) && (10..40).contains(&y);
        let shelf = (40..44).contains(&x) && (0..30).contains(&y);
        Some(if wall || pillar || shelf {
            Cell::Occupied
        } else {
            Cell::Free
        })
    };
    let cells = |corner: bool| -> Vec<Cell> {
        (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| match arena(i, j) {
                Some(c) => c,
                None if corner && (i, j) == (w - 3, h - 3) => Cell::Free,
                None => Cell::Unknown,
            })
            .collect()
    };
    let origin = [-3.0, -2.0, 0.3];
    let part = OccupancyMap::from_cells(w, h, res, origin, cells(false)).expect("map");
    let whole = OccupancyMap::from_cells(w, h, res, origin, cells(true)).expect("map");
    let goal = part.cell_center(200, 130);
    let starts = [
        part.cell_center(160, 100),
        part.cell_center(180, 130),
        part.cell_center(205, 100),
        part.cell_center(20, 20),
        part.grid_to_world([-5.0, 10.0]),
    ];
    for mesher in [MapMesher::Auto, MapMesher::Quadtree] {
        let opts = MapOptions {
            mesher,
            ..MapOptions::default()
        };
        let build = |map: &OccupancyMap| {
            map.planner(goal, radius, &opts, &PlannerOptions::default())
                .expect("planner")
        };
        let (a, b) = (build(&part), build(&whole));
        let statuses: Vec<String> = starts
            .iter()
            .map(|&s| {
                let (p, q) = (a.plan(s), b.plan(s));
                assert_eq!(
                    p.status.as_str(),
                    q.status.as_str(),
                    "{mesher:?} from {s:?}"
                );
                assert!(
                    (p.length - q.length).abs() <= 1e-9,
                    "{mesher:?} from {s:?}: {} vs {}",
                    p.length,
                    q.length
                );
                for (u, v) in p.points.iter().zip(&q.points) {
                    assert!((u[0] - v[0]).hypot(u[1] - v[1]) <= 1e-9, "{mesher:?}");
                }
                p.status.as_str().to_string()
            })
            .collect();
        assert_eq!(
            statuses,
            [
                "reached_goal",
                "reached_goal",
                "reached_goal",
                "start_in_obstacle",
                "outside_workspace"
            ],
            "{mesher:?}"
        );
    }
    let refused = match part.planner(
        part.cell_center(20, 20),
        radius,
        &MapOptions::default(),
        &PlannerOptions::default(),
    ) {
        Ok(_) => panic!("a goal in an unknown cell is refused"),
        Err(e) => e.to_string(),
    };
    assert!(refused.contains("column 20, row 20"), "{refused}");
}
