//! A balanced quadtree mesh of the free blocks of a grid: the mesher for occupancy grids.
//!
//! A grid of square blocks, each [`Block::Free`], [`Block::Blocked`] or [`Block::Goal`], is
//! covered by the leaves of a quadtree: square nodes of 2^k × 2^k blocks, as large as
//! [`QuadtreeOptions::max_level`] allows in open space, smaller where a side would face
//! free and non-free blocks at once, down to one block, with neighbouring leaves at most one
//! level apart (2:1 balance). Each leaf is cut into right isosceles triangles:
//!
//! ```text
//!   no finer neighbour        finer neighbours on some sides (their corners are midpoints)
//!   +---------+               +----+----+
//!   |       / |               | \  |  / |
//!   |     /   |               |   \|/   |
//!   |   /     |               +----c----+     c: the leaf's centre; a side without a
//!   | /       |               |   / \   |        midpoint gives one triangle c-a-b
//!   +---------+               | /     \ |
//!                             +---------+
//! ```
//!
//! No triangle has an obtuse angle, so every cotangent weight is zero or positive: the P1
//! stiffness matrix is an M-matrix and the discrete potential has no interior local minimum,
//! as on a constrained Delaunay mesh. Boundary edges are the sides of leaves that face
//! blocked blocks or the grid's edge (tag [`BoundaryTag::Wall`]) or goal blocks
//! ([`BoundaryTag::Goal`]`(0)`), so the mesh covers exactly the union of the free blocks;
//! a leaf larger than one block is a leaf only where each of its sides faces one kind of
//! block all along (a straight wall lets open floor's large leaves reach it).
//!
//! Building it is a few passes over the grid (an eligibility pyramid, the leaves, the
//! balance) and one over the leaves (the triangles, their vertices numbered in a window of
//! rows), linear in the number of blocks; there is no point location and no refinement
//! loop. An occupancy grid meshed at half a cell is held as its cells
//! ([`BlockGrid::halved`]), never written out at four times the size.
//!
//! ```
//! use harmonic_mesh::quadtree::{Block, BlockGrid, QuadtreeOptions, quadtree_mesh};
//! use harmonic_mesh::{BoundaryTag, Point};
//! // A 16 × 16 room with the goal block in a corner and a wall stub.
//! let mut blocks = vec![Block::Free; 16 * 16];
//! blocks[1 * 16 + 1] = Block::Goal;
//! for j in 0..8 {
//!     blocks[j * 16 + 8] = Block::Blocked;
//! }
//! let grid = BlockGrid::new(16, 16, blocks)?;
//! let mesh = quadtree_mesh(&grid, &QuadtreeOptions::default(), |x, y| Point::new(x, y))?;
//! let q = mesh.quality();
//! assert!(q.max_angle_deg <= 90.0 + 1e-9);
//! // The mesh covers the free blocks exactly: 256 − 1 − 8 of area 1 each.
//! assert!((q.area - 247.0).abs() < 1e-9);
//! assert!(mesh.boundary_edges().iter().any(|e| e.tag == BoundaryTag::Goal(0)));
//! # Ok::<(), harmonic_mesh::MeshError>(())
//! ```

use rayon::prelude::*;

use crate::{BoundaryTag, Mesh, MeshError, Point};

/// One block of a [`BlockGrid`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    /// Not part of the mesh; its sides facing free blocks are walls.
    Blocked,
    /// Covered by the mesh.
    Free,
    /// Not part of the mesh; its sides facing free blocks are goal boundary (`Goal(0)`).
    Goal,
}

/// A grid of blocks, row by row from the bottom: block `(i, j)` covers `[i, i + 1] × [j, j + 1]`
/// in block units.
#[derive(Clone, Debug)]
pub struct BlockGrid {
    width: usize,
    height: usize,
    /// The blocks as given: each stands for 2^`shift` × 2^`shift` blocks of the grid.
    blocks: Vec<Block>,
    shift: u32,
}

/// The most blocks a grid may have (2^30, about a billion: the vertex numbers stay in `u32`).
pub const MAX_BLOCKS: usize = 1 << 30;

impl BlockGrid {
    /// A grid of `width × height` blocks listed row by row from the bottom.
    pub fn new(width: usize, height: usize, blocks: Vec<Block>) -> Result<BlockGrid, MeshError> {
        if width == 0
            || height == 0
            || width.checked_mul(height) != Some(blocks.len())
            || blocks.len() > MAX_BLOCKS
        {
            return Err(MeshError::BlockGridSize {
                width,
                height,
                blocks: blocks.len(),
                max: MAX_BLOCKS,
            });
        }
        Ok(BlockGrid {
            width,
            height,
            blocks,
            shift: 0,
        })
    }

    /// A grid of `2 width × 2 height` blocks, each of the `width × height` given (row by
    /// row from the bottom) standing for 2 × 2 of them: an occupancy grid's cells as half
    /// cells, without a copy four times the size.
    pub fn halved(width: usize, height: usize, cells: Vec<Block>) -> Result<BlockGrid, MeshError> {
        let given = cells.len();
        let size_error = || MeshError::BlockGridSize {
            width: 2 * width,
            height: 2 * height,
            blocks: 4 * given,
            max: MAX_BLOCKS,
        };
        if cells.len() > MAX_BLOCKS / 4 {
            return Err(size_error());
        }
        let mut grid = BlockGrid::new(width, height, cells).map_err(|_| size_error())?;
        grid.width *= 2;
        grid.height *= 2;
        grid.shift = 1;
        Ok(grid)
    }

    /// Blocks per row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The block in column `i`, row `j`.
    pub fn block(&self, i: usize, j: usize) -> Block {
        self.blocks[(j >> self.shift) * (self.width >> self.shift) + (i >> self.shift)]
    }

    /// Whether the lattice point `(x, y)` touches only free blocks (so a vertex there is
    /// not on the boundary).
    fn interior_corner(&self, x: usize, y: usize) -> bool {
        let (x, y) = (x as isize, y as isize);
        [(x - 1, y - 1), (x, y - 1), (x - 1, y), (x, y)]
            .into_iter()
            .all(|(i, j)| self.outside(i, j) == Block::Free)
    }

    /// What lies outside a side: the block there, or `Blocked` past the grid's edge.
    fn outside(&self, i: isize, j: isize) -> Block {
        if i >= 0 && j >= 0 && (i as usize) < self.width && (j as usize) < self.height {
            self.block(i as usize, j as usize)
        } else {
            Block::Blocked
        }
    }
}

/// Options of [`quadtree_mesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadtreeOptions {
    /// The largest leaf is 2^`max_level` blocks on a side (at most 15).
    pub max_level: u8,
    /// Keep the free space's interior connected through vertices off the boundary, so that
    /// a passage one block wide is not sealed by the Dirichlet values of its walls. A node
    /// larger than one block is a leaf only if (besides the rule above) the corners of it
    /// that touch no block that is not free are there and joined along its sides (not just
    /// two opposite ones), no side of it that faces free blocks has both ends on the
    /// boundary, and it does not touch a goal block. A leaf cut in two whose only such
    /// corner is one is cut through that corner.
    ///
    /// With blocks of half a cell (every cell of a grid as 2 × 2 blocks: [`BlockGrid::halved`]) every free
    /// cell is then either a leaf of one or more cells with such corners, or split into its
    /// four half cells around a centre vertex with midpoints on its sides: the vertices off
    /// the boundary are joined, from any free cell to any 4-neighbouring free cell, by edges
    /// of positive weight, and every triangle has at least one of them. The discrete
    /// potential is then positive below the walls' value on every free cell 4-connected to
    /// the goal, and a descent from any point of the mesh reaches the goal.
    pub interior_vertices: bool,
}

impl Default for QuadtreeOptions {
    fn default() -> Self {
        QuadtreeOptions {
            max_level: 3,
            interior_vertices: false,
        }
    }
}

/// The leaf level of a block that is not free.
const NOT_FREE: u8 = u8::MAX;

/// One level of a [`Pyramid`]: `(width, height, all free, any free)`.
type Level = (usize, usize, Vec<bool>, Vec<bool>);

/// Per level, whether each 2^k node's blocks are all free, and whether any of them is.
struct Pyramid {
    /// The level of the blocks as the grid holds them (1 for a [`BlockGrid::halved`] grid);
    /// a node below it lies inside one of them.
    first: u8,
    /// `(width, height, all free, any free)` of each level from `first` on; a block as
    /// given is all or nothing, so level `first` keeps only the first.
    levels: Vec<Level>,
}

impl Pyramid {
    fn new(grid: &BlockGrid, max_level: u8) -> Pyramid {
        let first = grid.shift as u8;
        let free: Vec<bool> = grid.blocks.par_iter().map(|&b| b == Block::Free).collect();
        let mut levels = vec![(grid.width >> first, grid.height >> first, free, Vec::new())];
        for _ in first..max_level.max(first) {
            let (pw, ph, all, any) = levels.last().expect("the first level is there");
            let (pw, ph) = (*pw, *ph);
            let any = if any.is_empty() { all } else { any };
            let (nw, nh) = (pw.div_ceil(2), ph.div_ceil(2));
            let mut next_all = vec![false; nw * nh];
            let mut next_any = vec![false; nw * nh];
            let at = |e: &[bool], i: usize, j: usize| i < pw && j < ph && e[j * pw + i];
            // Row by row on rayon's pool (each row of the level reads two rows below it).
            next_all
                .par_chunks_mut(nw)
                .zip(next_any.par_chunks_mut(nw))
                .enumerate()
                .for_each(|(j, (row_all, row_any))| {
                    for i in 0..nw {
                        let kids = [
                            (2 * i, 2 * j),
                            (2 * i + 1, 2 * j),
                            (2 * i, 2 * j + 1),
                            (2 * i + 1, 2 * j + 1),
                        ];
                        row_all[i] = kids.iter().all(|&(x, y)| at(all, x, y));
                        row_any[i] = kids.iter().any(|&(x, y)| at(any, x, y));
                    }
                });
            levels.push((nw, nh, next_all, next_any));
        }
        Pyramid { first, levels }
    }

    /// Level `k`'s `(width, height, all free, any free)` and `(i, j)` moved up to the
    /// first level when `k` is below it.
    fn level(&self, k: u8, i: usize, j: usize) -> (&Level, usize, usize) {
        match k.checked_sub(self.first) {
            Some(up) => (&self.levels[up as usize], i, j),
            None => {
                let down = self.first - k;
                (&self.levels[0], i >> down, j >> down)
            }
        }
    }

    fn all_free(&self, k: u8, i: usize, j: usize) -> bool {
        let ((w, h, e, _), i, j) = self.level(k, i, j);
        i < *w && j < *h && e[j * w + i]
    }

    fn any_free(&self, k: u8, i: usize, j: usize) -> bool {
        let ((w, h, all, any), i, j) = self.level(k, i, j);
        let e = if any.is_empty() { all } else { any };
        i < *w && j < *h && e[j * w + i]
    }
}

/// The four strips of blocks just outside a node's sides (bottom, right, top, left), each
/// as the block coordinates of its `2^k` blocks.
fn strips(n: Node) -> [impl Iterator<Item = (isize, isize)>; 4] {
    let (x0, y0) = n.origin();
    let (x0, y0, s) = (x0 as isize, y0 as isize, 1isize << n.k);
    [
        (x0, y0 - 1, 1, 0),
        (x0 + s, y0, 0, 1),
        (x0, y0 + s, 1, 0),
        (x0 - 1, y0, 0, 1),
    ]
    .map(|(x, y, dx, dy)| (0..s).map(move |t| (x + t * dx, y + t * dy)))
}

/// Whether a node may be a leaf: its blocks are all free and each strip outside its sides is
/// all free, all blocked (or past the grid's edge) or all goal, so a side facing the
/// boundary is one boundary edge with one tag.
///
/// With `interior_vertices` a node of more than one block must also keep its interior
/// joined (see [`QuadtreeOptions::interior_vertices`]).
fn eligible(grid: &BlockGrid, pyramid: &Pyramid, n: Node, interior_vertices: bool) -> bool {
    if !pyramid.all_free(n.k, n.i as usize, n.j as usize) {
        return false;
    }
    on_open_floor(pyramid, n) || eligible_by_its_blocks(grid, n, interior_vertices)
}

/// Whether the eight nodes of `n`'s level around it are all free: then every strip outside
/// its sides is free, no goal block is near and each of its corners touches free blocks
/// only, so a free `n` is eligible without looking at its blocks one by one.
fn on_open_floor(pyramid: &Pyramid, n: Node) -> bool {
    let (i, j) = (n.i as usize, n.j as usize);
    i > 0 && j > 0 && (j - 1..=j + 1).all(|y| (i - 1..=i + 1).all(|x| pyramid.all_free(n.k, x, y)))
}

/// [`eligible`] for a free node, from the blocks along its sides and at its corners.
fn eligible_by_its_blocks(grid: &BlockGrid, n: Node, interior_vertices: bool) -> bool {
    let uniform = strips(n).into_iter().all(|mut strip| {
        let (x, y) = strip.next().expect("a strip has at least one block");
        let first = grid.outside(x, y);
        strip.all(|(x, y)| grid.outside(x, y) == first)
    });
    if !uniform || !interior_vertices || n.k == 0 {
        return uniform;
    }
    let (x0, y0) = n.origin();
    let s = 1usize << n.k;
    let corners = [(x0, y0), (x0 + s, y0), (x0 + s, y0 + s), (x0, y0 + s)];
    let ring = [
        (x0 as isize - 1, y0 as isize - 1),
        ((x0 + s) as isize, y0 as isize - 1),
        (x0 as isize - 1, (y0 + s) as isize),
        ((x0 + s) as isize, (y0 + s) as isize),
    ];
    let touches_goal = ring
        .into_iter()
        .chain(strips(n).into_iter().flatten())
        .any(|(x, y)| grid.outside(x, y) == Block::Goal);
    if touches_goal {
        return false;
    }
    let inner = corners.map(|(x, y)| grid.interior_corner(x, y));
    let joined = !matches!(
        inner,
        [false, false, false, false] | [true, false, true, false] | [false, true, false, true]
    );
    // Side q runs from corner q to corner q + 1 (bottom, right, top, left, as `strips`).
    let sealed_side = strips(n).into_iter().enumerate().any(|(q, mut strip)| {
        let (x, y) = strip.next().expect("a strip has at least one block");
        grid.outside(x, y) == Block::Free && !inner[q] && !inner[(q + 1) % 4]
    });
    joined && !sealed_side
}

/// Writes level `k` (stored as `k + 1`, see [`Leaves::level`]) into the blocks node `n`
/// covers, in `rows`: the grid's rows from `first_row` on, `w` blocks each (clipped to the
/// grid's `w` × `height`).
fn paint(rows: &mut [u8], first_row: usize, w: usize, height: usize, n: Node, k: u8) {
    let (bi, bj) = n.origin();
    let s = 1usize << n.k;
    for y in bj..(bj + s).min(height) {
        let at = (y - first_row) * w;
        rows[at + bi..at + (bi + s).min(w)].fill(k + 1);
    }
}

/// The leaves: the level of the leaf holding each block ([`Leaves::at`] says [`NOT_FREE`]
/// for blocks that are not free).
struct Leaves<'a> {
    grid: &'a BlockGrid,
    /// One plus the level of the leaf holding each block, 0 for a block that is not free:
    /// allocated zeroed, so the pages of wide blocked or unknown areas are never touched and
    /// the others are first written by the bands in parallel (filled with a marker, the
    /// array was written and faulted in on one thread first: 4–5 ms of willow_garage's
    /// 6.8 M half-cell blocks).
    level: Vec<u8>,
    /// Every node made a leaf so far, split ones included ([`Leaves::into_leaves`] keeps
    /// the others).
    made: Vec<Node>,
}

impl<'a> Leaves<'a> {
    /// The largest eligible nodes, top-down from `max_level`; every leaf is pushed on `todo`.
    /// Each row of top-level nodes covers its own rows of blocks, so the rows are walked on
    /// rayon's pool and their leaves joined in row order: the same leaves, in the same
    /// order, at any thread count.
    fn new(
        grid: &'a BlockGrid,
        pyramid: &Pyramid,
        opts: &QuadtreeOptions,
        todo: &mut Vec<Node>,
    ) -> Self {
        let max_level = opts.max_level;
        let w = grid.width;
        let band = (1usize << max_level) * w;
        let mut level = vec![0; w * grid.height];
        let tw = w.div_ceil(1 << max_level);
        let made: Vec<Vec<Node>> = level
            .par_chunks_mut(band)
            .enumerate()
            .map(|(j, rows)| {
                // `rows` holds the blocks of rows j·2^max_level onwards.
                let first_row = j << max_level;
                let mut made = Vec::new();
                let mut stack: Vec<Node> = Vec::new();
                for i in 0..tw {
                    stack.push(Node {
                        k: max_level,
                        i: i as u32,
                        j: j as u32,
                    });
                    while let Some(n) = stack.pop() {
                        let (bi, bj) = n.origin();
                        // Nothing to mesh below a node with no free block (wide blocked or
                        // unknown areas are skipped whole, not visited block by block).
                        if bi >= w
                            || bj >= grid.height
                            || !pyramid.any_free(n.k, n.i as usize, n.j as usize)
                        {
                            continue;
                        }
                        let leaf = if n.k == 0 {
                            grid.block(bi, bj) == Block::Free
                        } else {
                            eligible(grid, pyramid, n, opts.interior_vertices)
                        };
                        if leaf {
                            paint(rows, first_row, w, grid.height, n, n.k);
                            made.push(n);
                        } else if n.k > 0 {
                            stack.extend(n.children());
                        }
                    }
                }
                made
            })
            .collect();
        let made = made.concat();
        todo.extend_from_slice(&made);
        Leaves { grid, level, made }
    }

    fn fill(&mut self, n: Node, k: u8) {
        paint(&mut self.level, 0, self.grid.width, self.grid.height, n, k);
    }

    fn at(&self, i: isize, j: isize) -> u8 {
        if i >= 0 && j >= 0 && (i as usize) < self.grid.width && (j as usize) < self.grid.height {
            self.level[j as usize * self.grid.width + i as usize]
                .checked_sub(1)
                .unwrap_or(NOT_FREE)
        } else {
            NOT_FREE
        }
    }

    /// The leaves (the nodes made leaves and never split: a split node's first block
    /// belongs to a finer leaf since), ordered by their first block, row by row.
    fn leaves(&mut self) -> Vec<Node> {
        let w = self.grid.width;
        let mut made = std::mem::take(&mut self.made);
        made.retain(|n| {
            let (x, y) = n.origin();
            self.level[y * w + x] == n.k + 1
        });
        // No two leaves share a first block: the order is the same on any number of threads.
        made.par_sort_unstable_by_key(|n| {
            let (x, y) = n.origin();
            (y, x)
        });
        made
    }

    /// Splits leaves until neighbours across a side differ by at most one level.
    fn balance(&mut self, todo: &mut Vec<Node>) {
        while let Some(n) = todo.pop() {
            let (bi, bj) = n.origin();
            if self.level[bj * self.grid.width + bi] != n.k + 1 {
                continue; // split since it was pushed; its children are on the stack
            }
            let s = 1isize << n.k;
            let (x0, y0) = (bi as isize, bj as isize);
            // One block outside each side: a leaf more than one level coarser than `n` that
            // holds any block of a side's strip holds all of it (it is aligned to its size,
            // a multiple of the side's), so it holds the first, and once the leaf there is
            // fine enough, so are all of the strip's.
            for (x, y) in [(x0, y0 - 1), (x0, y0 + s), (x0 - 1, y0), (x0 + s, y0)] {
                loop {
                    let m = self.at(x, y);
                    if m == NOT_FREE || m <= n.k + 1 {
                        break;
                    }
                    let big = Node {
                        k: m,
                        i: (x as u32) >> m,
                        j: (y as u32) >> m,
                    };
                    for c in big.children() {
                        self.fill(c, m - 1);
                        self.made.push(c);
                        todo.push(c);
                    }
                }
            }
        }
    }
}

/// A quadtree node: level `k`, position `(i, j)` in units of 2^k blocks.
#[derive(Clone, Copy, Debug)]
struct Node {
    k: u8,
    i: u32,
    j: u32,
}

impl Node {
    fn origin(self) -> (usize, usize) {
        ((self.i as usize) << self.k, (self.j as usize) << self.k)
    }

    fn children(self) -> [Node; 4] {
        let (k, i, j) = (self.k - 1, 2 * self.i, 2 * self.j);
        [
            Node { k, i, j },
            Node { k, i: i + 1, j },
            Node { k, i, j: j + 1 },
            Node {
                k,
                i: i + 1,
                j: j + 1,
            },
        ]
    }
}

/// Vertices on the block-corner lattice, numbered as first used, over a window of rows:
/// the leaves come row by row of their first block and a leaf of side s spans s + 1 rows
/// of corners, so a row below the current leaves' is never asked for again and only the
/// `rows` rows from there (the largest side + 1) need numbers. `id` holds the number plus
/// one (0 where there is none yet), row `y` in slot row `y % rows`.
struct Lattice<F> {
    width: usize,
    rows: usize,
    /// The lowest row still in the window.
    low: usize,
    id: Vec<u32>,
    points: Vec<Point>,
    to_world: F,
}

impl<F: Fn(f64, f64) -> Point> Lattice<F> {
    fn new(width: usize, height: usize, max_side: usize, to_world: F) -> Self {
        let rows = (max_side + 1).min(height + 1);
        Lattice {
            width,
            rows,
            low: 0,
            id: vec![0; rows * (width + 1)],
            points: Vec::new(),
            to_world,
        }
    }

    /// Moves the window up to start at row `y` (rows below it are done with).
    fn advance(&mut self, y: usize) {
        let stride = self.width + 1;
        for r in self.low..y.min(self.low + self.rows) {
            let slot = (r % self.rows) * stride;
            self.id[slot..slot + stride].fill(0);
        }
        self.low = self.low.max(y);
    }

    fn vertex(&mut self, x: usize, y: usize) -> u32 {
        debug_assert!(y >= self.low && y < self.low + self.rows);
        let slot = &mut self.id[(y % self.rows) * (self.width + 1) + x];
        if *slot == 0 {
            self.points.push((self.to_world)(x as f64, y as f64));
            *slot = self.points.len() as u32;
        }
        *slot - 1
    }
}

/// The balanced quadtree mesh of `grid`'s free blocks (see the module documentation);
/// `to_world` maps block coordinates to the mesh's coordinates (it must keep orientation:
/// a rotation, a translation and a positive scale).
///
/// Errors when no block is free, when `max_level` is above 15, or when `to_world` turns a
/// triangle clockwise or gives non-finite points.
pub fn quadtree_mesh(
    grid: &BlockGrid,
    opts: &QuadtreeOptions,
    to_world: impl Fn(f64, f64) -> Point,
) -> Result<Mesh, MeshError> {
    if opts.max_level > 15 {
        return Err(MeshError::InvalidOption {
            name: "max_level",
            value: f64::from(opts.max_level),
            reason: "the largest leaf is 2^max_level blocks, and max_level is at most 15",
        });
    }
    if !grid.blocks.contains(&Block::Free) {
        return Err(MeshError::NoFreeBlock);
    }
    let pyramid = Pyramid::new(grid, opts.max_level);
    let mut todo = Vec::new();
    let mut leaves = Leaves::new(grid, &pyramid, opts, &mut todo);
    drop(pyramid);
    leaves.balance(&mut todo);

    let (w, h) = (grid.width, grid.height);
    let mut lattice = Lattice::new(w, h, 1 << opts.max_level, to_world);
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut boundary: Vec<(u32, u32, BoundaryTag)> = Vec::new();
    for leaf in leaves.leaves() {
        let ((x, y), k) = (leaf.origin(), leaf.k);
        lattice.advance(y);
        let s = 1usize << k;
        let corners = [(x, y), (x + s, y), (x + s, y + s), (x, y + s)];
        let c = corners.map(|(a, b)| lattice.vertex(a, b));
        // A side facing the boundary faces one kind of block all along (eligibility).
        for (q, mut strip) in strips(leaf).into_iter().enumerate() {
            let (ox, oy) = strip.next().expect("a strip has at least one block");
            let tag = match grid.outside(ox, oy) {
                Block::Free => continue,
                Block::Blocked => BoundaryTag::Wall,
                Block::Goal => BoundaryTag::Goal(0),
            };
            boundary.push((c[q], c[(q + 1) % 4], tag));
        }
        // A side has a midpoint vertex when a leaf one level finer lies across it.
        let finer = |ox: isize, oy: isize| k > 0 && leaves.at(ox, oy) == k - 1;
        let (xi, yi, si, hi) = (x as isize, y as isize, s as isize, (s / 2) as isize);
        let mid_at = [
            finer(xi, yi - 1) || finer(xi + hi, yi - 1),
            finer(xi + si, yi) || finer(xi + si, yi + hi),
            finer(xi, yi + si) || finer(xi + hi, yi + si),
            finer(xi - 1, yi) || finer(xi - 1, yi + hi),
        ];
        if !mid_at.contains(&true) {
            // Alternate the diagonal so open floor is cut symmetrically; with interior
            // vertices kept, a leaf with one corner off the boundary is cut through it,
            // so neither triangle has all its vertices on the boundary.
            let inner = corners.map(|(a, b)| grid.interior_corner(a, b));
            let through_02 = match (opts.interior_vertices, inner) {
                (true, [true, false, false, false] | [false, false, true, false]) => true,
                (true, [false, true, false, false] | [false, false, false, true]) => false,
                _ => ((x >> k) + (y >> k)).is_multiple_of(2),
            };
            if through_02 {
                triangles.push([c[0], c[1], c[2]]);
                triangles.push([c[0], c[2], c[3]]);
            } else {
                triangles.push([c[0], c[1], c[3]]);
                triangles.push([c[1], c[2], c[3]]);
            }
            continue;
        }
        let centre = lattice.vertex(x + s / 2, y + s / 2);
        let mids = [
            (x + s / 2, y),
            (x + s, y + s / 2),
            (x + s / 2, y + s),
            (x, y + s / 2),
        ];
        for q in 0..4 {
            let (a, b) = (c[q], c[(q + 1) % 4]);
            if mid_at[q] {
                let m = lattice.vertex(mids[q].0, mids[q].1);
                triangles.push([centre, a, m]);
                triangles.push([centre, m, b]);
            } else {
                triangles.push([centre, a, b]);
            }
        }
    }
    Ok(Mesh::from_parts(lattice.points, triangles, &boundary)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The open-floor shortcut only ever says what the blocks say: on seeded grids (whole
    /// and halved, with goal blocks), every free node it accepts is eligible block by block.
    #[test]
    fn open_floor_nodes_are_eligible_by_their_blocks() {
        for (seed, one_in) in [(3u64, 7u64), (5, 30), (9, 200)] {
            let mut cells = seeded_cells(70, 45, seed, one_in);
            cells[17 * 70 + 33] = Block::Goal;
            for grid in [
                BlockGrid::new(70, 45, cells.clone()).expect("sizes match"),
                BlockGrid::halved(70, 45, cells).expect("sizes match"),
            ] {
                let pyramid = Pyramid::new(&grid, 4);
                let mut shortcuts = 0;
                for k in 0..=4u8 {
                    for j in 0..(grid.height >> k) as u32 {
                        for i in 0..(grid.width >> k) as u32 {
                            let n = Node { k, i, j };
                            if pyramid.all_free(k, i as usize, j as usize)
                                && on_open_floor(&pyramid, n)
                            {
                                shortcuts += 1;
                                for interior in [false, true] {
                                    assert!(
                                        eligible_by_its_blocks(&grid, n, interior),
                                        "seed {seed}: {n:?}"
                                    );
                                }
                            }
                        }
                    }
                }
                assert!(
                    shortcuts > 10,
                    "seed {seed}: the shortcut was taken {shortcuts} times"
                );
            }
        }
    }

    fn room(w: usize, h: usize, blocked: &[(usize, usize)], goal: (usize, usize)) -> BlockGrid {
        let mut blocks = vec![Block::Free; w * h];
        for &(i, j) in blocked {
            blocks[j * w + i] = Block::Blocked;
        }
        blocks[goal.1 * w + goal.0] = Block::Goal;
        BlockGrid::new(w, h, blocks).expect("sizes match")
    }

    /// `w × h` cells, about one in `one_in` blocked (xorshift from `seed`), the rest free.
    fn seeded_cells(w: usize, h: usize, mut seed: u64, one_in: u64) -> Vec<Block> {
        (0..w * h)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                if seed.is_multiple_of(one_in) {
                    Block::Blocked
                } else {
                    Block::Free
                }
            })
            .collect()
    }

    #[test]
    fn leaves_are_balanced_and_cover_the_free_blocks() {
        let rooms = [room(77, 53, &[(10, 10), (11, 10), (30, 2)], (3, 20))];
        // Scattered blocks: many small leaves beside large ones, so the balance splits
        // leaves several levels coarser than their neighbours (checked one block per side).
        let scattered = [(11u64, 40u64), (12, 150), (13, 600)]
            .map(|(seed, one_in)| BlockGrid::new(90, 70, seeded_cells(90, 70, seed, one_in)));
        let coarse: Vec<bool> = rooms
            .into_iter()
            .chain(scattered.into_iter().flatten())
            .map(|grid| balanced_cover(&grid))
            .collect();
        assert!(
            coarse[0] && coarse[3],
            "open floor gets large leaves: {coarse:?}"
        );
    }

    /// Checks that `grid`'s leaves cover its free blocks, are balanced and face one kind of
    /// block along each side; whether any leaf is of level 3 or more.
    fn balanced_cover(grid: &BlockGrid) -> bool {
        let opts = QuadtreeOptions {
            max_level: 4,
            ..Default::default()
        };
        let grid = grid.clone();
        let pyramid = Pyramid::new(&grid, opts.max_level);
        let mut todo = Vec::new();
        let mut leaves = Leaves::new(&grid, &pyramid, &opts, &mut todo);
        leaves.balance(&mut todo);
        let (w, h) = (grid.width as isize, grid.height as isize);
        let mut coarse = false;
        for y in 0..h {
            for x in 0..w {
                let k = leaves.at(x, y);
                assert_eq!(k == NOT_FREE, grid.outside(x, y) != Block::Free);
                if k == NOT_FREE {
                    continue;
                }
                coarse |= k >= 3;
                for (ox, oy) in [(x + 1, y), (x, y + 1)] {
                    let m = leaves.at(ox, oy);
                    if m != NOT_FREE {
                        assert!(k.abs_diff(m) <= 1, "({x}, {y}) level {k} beside {m}");
                    }
                }
                // Each side of a leaf faces one kind of block all along, or free ones.
                let s = 1isize << k;
                let node = Node {
                    k,
                    i: (x >> k) as u32,
                    j: (y >> k) as u32,
                };
                let (x0, y0) = ((x >> k) << k, (y >> k) << k);
                assert!(x0 + s <= w && y0 + s <= h);
                for strip in strips(node) {
                    let kinds: Vec<Block> = strip.map(|(a, b)| grid.outside(a, b)).collect();
                    let mixed = kinds.windows(2).any(|p| p[0] != p[1]);
                    assert!(!mixed || kinds.iter().all(|&b| b == Block::Free) || k == 0);
                    if mixed {
                        assert_eq!(k, 0, "({x}, {y}): a mixed side on a coarse leaf");
                    }
                }
            }
        }
        coarse
    }

    #[test]
    fn mesh_is_conforming_non_obtuse_and_exact() {
        let blocked: Vec<(usize, usize)> = (0..12).map(|j| (20, j)).collect();
        let grid = room(40, 30, &blocked, (35, 5));
        let opts = QuadtreeOptions {
            max_level: 4,
            ..Default::default()
        };
        let mesh = quadtree_mesh(&grid, &opts, |x, y| {
            // A rotated, shifted, scaled frame, as a map's origin gives.
            let (s, c) = 0.3f64.sin_cos();
            Point::new(-7.0 + 0.05 * (c * x - s * y), 3.0 + 0.05 * (s * x + c * y))
        })
        .expect("meshes");
        let q = mesh.quality();
        assert!(q.max_angle_deg <= 90.0 + 1e-6, "{q:?}");
        assert!(
            (q.area - 0.0025 * (1200.0 - 12.0 - 1.0)).abs() < 1e-9,
            "{q:?}"
        );
        assert_eq!(
            q.holes, 1,
            "the goal block is a hole; the wall stub touches the edge"
        );
        assert!(
            mesh.triangles().len() < 2 * 1187,
            "coarse leaves in the open"
        );
        let goal_edges = mesh
            .boundary_edges()
            .iter()
            .filter(|e| e.tag == BoundaryTag::Goal(0))
            .count();
        assert_eq!(goal_edges, 4);
    }

    /// Cells of a `w × h` grid (row by row, `true` free, the goal at `goal`) as half-cell
    /// blocks, meshed with `interior_vertices`, as the map planner does.
    fn half_cell_mesh(w: usize, h: usize, free: &[bool], goal: (usize, usize)) -> Mesh {
        let blocks = (0..2 * h)
            .flat_map(|j| (0..2 * w).map(move |i| (i / 2, j / 2)))
            .map(|(i, j)| match ((i, j) == goal, free[j * w + i]) {
                (true, _) => Block::Goal,
                (false, true) => Block::Free,
                (false, false) => Block::Blocked,
            })
            .collect();
        let grid = BlockGrid::new(2 * w, 2 * h, blocks).expect("sizes match");
        let opts = QuadtreeOptions {
            max_level: 4,
            interior_vertices: true,
        };
        quadtree_mesh(&grid, &opts, |x, y| Point::new(0.5 * x, 0.5 * y)).expect("meshes")
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 64,
            failure_persistence: None,
            ..Default::default()
        })]

        /// With `interior_vertices`, on random grids: no obtuse angle, every triangle has a
        /// vertex off the boundary, and every vertex off the boundary in a free cell that
        /// free cells join (4-connected) to the goal's cell is joined to a goal vertex by
        /// edges of positive weight (legs of the right triangles) through vertices off the
        /// boundary: no passage is sealed.
        #[test]
        fn interior_vertices_join_every_free_cell_to_the_goal(
            (w, h) in (3usize..14, 3usize..14),
            seed in proptest::prelude::any::<u64>(),
            blocked_in in 2u64..5,
        ) {
            let mut state = seed | 1;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state
            };
            let free: Vec<bool> = (0..w * h).map(|_| next() % blocked_in != 0).collect();
            let goal = ((next() % w as u64) as usize, (next() % h as u64) as usize);
            let cell_free = |i: isize, j: isize| {
                i >= 0 && j >= 0 && (i as usize) < w && (j as usize) < h
                    && free[j as usize * w + i as usize]
                    && (i as usize, j as usize) != goal
            };
            proptest::prop_assume!((0..w * h).any(|k| cell_free((k % w) as isize, (k / w) as isize)));
            let mesh = half_cell_mesh(w, h, &free, goal);
            proptest::prop_assert!(mesh.quality().max_angle_deg <= 90.0 + 1e-9);
            let nv = mesh.vertices().len();
            let (mut wall, mut at_goal) = (vec![false; nv], vec![false; nv]);
            for e in mesh.boundary_edges() {
                for v in e.vertices {
                    match e.tag {
                        BoundaryTag::Goal(_) => at_goal[v as usize] = true,
                        _ => wall[v as usize] = true,
                    }
                }
            }
            let inside = |v: u32| !wall[v as usize] && !at_goal[v as usize];
            for t in mesh.triangles() {
                proptest::prop_assert!(t.iter().any(|&v| inside(v)), "a triangle {t:?} on the boundary");
            }
            // Union-find over vertices, joined along legs between vertices off the walls.
            let mut parent: Vec<usize> = (0..nv).collect();
            fn root(p: &mut [usize], mut v: usize) -> usize {
                while p[v] != v {
                    p[v] = p[p[v]];
                    v = p[v];
                }
                v
            }
            let pts = mesh.vertices();
            for t in mesh.triangles() {
                for k in 0..3 {
                    let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                    // Edge a–b is a leg unless the right angle is at c.
                    let (u, v) = (pts[a as usize] - pts[c as usize], pts[b as usize] - pts[c as usize]);
                    let right_at_c = (u.x * v.x + u.y * v.y).abs() < 1e-12;
                    if !right_at_c && !wall[a as usize] && !wall[b as usize] {
                        let (ra, rb) = (root(&mut parent, a as usize), root(&mut parent, b as usize));
                        parent[ra] = rb;
                    }
                }
            }
            let mut goal_roots = std::collections::HashSet::new();
            for v in 0..nv {
                if at_goal[v] && !wall[v] {
                    goal_roots.insert(root(&mut parent, v));
                }
            }
            // Free cells 4-connected to the goal's cell.
            let mut joined = vec![false; w * h];
            let mut stack: Vec<(isize, isize)> = [(0, 1), (1, 0), (0, -1), (-1, 0)]
                .iter()
                .map(|(di, dj)| (goal.0 as isize + di, goal.1 as isize + dj))
                .collect();
            while let Some((i, j)) = stack.pop() {
                if cell_free(i, j) && !joined[j as usize * w + i as usize] {
                    joined[j as usize * w + i as usize] = true;
                    stack.extend([(i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)]);
                }
            }
            for (v, p) in pts.iter().enumerate() {
                if !inside(v as u32) {
                    continue;
                }
                // A vertex off the boundary touches only free blocks: its cell is free.
                let (i, j) = (p.x.floor() as usize, p.y.floor() as usize);
                let (i, j) = (i.min(w - 1), j.min(h - 1));
                if joined[j * w + i] {
                    proptest::prop_assert!(
                        goal_roots.contains(&root(&mut parent, v)),
                        "vertex {:?} in cell ({i}, {j}) is cut off from the goal", p
                    );
                }
            }
        }
    }

    #[test]
    fn bad_grids_are_refused() {
        assert!(BlockGrid::new(3, 3, vec![Block::Free; 8]).is_err());
        let all_blocked = BlockGrid::new(2, 2, vec![Block::Blocked; 4]).expect("sizes match");
        let e = quadtree_mesh(&all_blocked, &QuadtreeOptions::default(), Point::new)
            .expect_err("nothing to mesh");
        assert!(e.to_string().contains("no free block"), "{e}");
        let grid = room(4, 4, &[], (0, 0));
        let opts = QuadtreeOptions {
            max_level: 16,
            ..Default::default()
        };
        assert!(quadtree_mesh(&grid, &opts, Point::new).is_err());
    }

    #[test]
    fn a_halved_grid_meshes_as_its_blocks_written_out() {
        // Seeded cells of every kind, at every largest leaf: the halved grid (one block per
        // cell) and the same grid written out block by block give the same mesh, vertex
        // for vertex and triangle for triangle.
        let (w, h) = (37, 23);
        let mut cells = seeded_cells(w, h, 0x9e37_79b9, 5);
        for k in [w + 5, 7 * w + 20, 18 * w + 30] {
            cells[k] = Block::Goal;
        }
        let mut blocks = Vec::with_capacity(4 * w * h);
        for row in cells.chunks_exact(w) {
            let start = blocks.len();
            blocks.extend(row.iter().flat_map(|&b| [b, b]));
            blocks.extend_from_within(start..);
        }
        let written = BlockGrid::new(2 * w, 2 * h, blocks).expect("sizes match");
        let halved = BlockGrid::halved(w, h, cells).expect("sizes match");
        for max_level in 0..=4 {
            for interior_vertices in [false, true] {
                let opts = QuadtreeOptions {
                    max_level,
                    interior_vertices,
                };
                let a = quadtree_mesh(&written, &opts, Point::new).expect("meshes");
                let b = quadtree_mesh(&halved, &opts, Point::new).expect("meshes");
                assert_eq!(a.vertices(), b.vertices(), "max_level {max_level}");
                assert_eq!(a.triangles(), b.triangles(), "max_level {max_level}");
                assert_eq!(a.boundary_edges(), b.boundary_edges());
            }
        }
        assert!(BlockGrid::halved(3, 3, vec![Block::Free; 8]).is_err());
    }

    #[test]
    fn the_mesh_is_the_same_at_any_thread_count() {
        // Rows of top-level nodes are walked on the pool; their leaves are joined in row
        // order, so the mesh is the same whatever the pool.
        let (w, h) = (90, 70);
        let mut cells = seeded_cells(w, h, 0x2545_f491_4f6c_dd1d, 7);
        cells[35 * w + 40] = Block::Goal;
        let grid = BlockGrid::halved(w, h, cells).expect("sizes match");
        let opts = QuadtreeOptions {
            max_level: 3,
            interior_vertices: true,
        };
        let mesh_with = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool")
                .install(|| quadtree_mesh(&grid, &opts, Point::new).expect("meshes"))
        };
        let one = mesh_with(1);
        for threads in [2, 3, 4] {
            let other = mesh_with(threads);
            assert_eq!(one.vertices(), other.vertices(), "{threads} threads");
            assert_eq!(one.triangles(), other.triangles(), "{threads} threads");
            assert_eq!(one.boundary_edges(), other.boundary_edges());
        }
    }
}
