//! The seed papers' published numbers, quoted beside ours by the examples and the README.
//!
//! Each constant names its source (paper, section, table); the values are as printed.

/// Garrido, Moreno, Blanco & Martín (2010), *Robotic Motion using Harmonic Functions and
/// Finite Elements*, Table 1: d (%) = d_i / d_D × 100 for the starts (0.5, 0.8) and
/// (0.2, 0.8), in the order of [`crate::tables::PAPER_ROWS`] (Neumann; Robin K = 1, 2, 3, 10;
/// Dirichlet; Robin K = 100, 1000).
pub const GARRIDO_TABLE1_D: [[f64; 2]; 8] = [
    [23.0, 9.0],
    [32.0, 23.0],
    [41.0, 41.0],
    [45.0, 50.0],
    [82.0, 64.0],
    [100.0, 100.0],
    [100.0, 100.0],
    [100.0, 100.0],
];

/// One column of Garrido et al. (2010), Table 2: SOR against FEM on the workspace of their
/// Figure 1, N grid points per side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SorFemSeconds {
    /// Grid points per side.
    pub n: usize,
    /// SOR, seconds.
    pub sor: f64,
    /// FEM, seconds.
    pub fem: f64,
}

/// Garrido et al. (2010), Table 2, measured on "a 1.6 GHz laptop PC" ([`GARRIDO_TABLE2_MACHINE`]).
pub const GARRIDO_TABLE2: [SorFemSeconds; 3] = [
    SorFemSeconds {
        n: 10,
        sor: 1.3720,
        fem: 0.2210,
    },
    SorFemSeconds {
        n: 20,
        sor: 5.2670,
        fem: 0.9910,
    },
    SorFemSeconds {
        n: 50,
        sor: 128.8550,
        fem: 7.5010,
    },
];

/// The machine of Garrido et al.'s Table 2.
pub const GARRIDO_TABLE2_MACHINE: &str = "a 1.6 GHz laptop PC (2010)";

/// Garrido et al.'s Table 2 entry for `n` grid points per side, if the paper has one.
pub fn garrido_table2(n: usize) -> Option<SorFemSeconds> {
    GARRIDO_TABLE2.iter().copied().find(|c| c.n == n)
}

/// One relaxation run of the ME766 term paper (*harmonic path planning*, "Results").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Me766Run {
    /// Which problem (1 or 2) and dimension (2 or 3).
    pub problem: u8,
    /// 2 or 3.
    pub dimension: u8,
    /// Grid points per side (100 in every run).
    pub grid: usize,
    /// The stopping accuracy (change between sweeps).
    pub accuracy: f64,
    /// Sweeps to reach it.
    pub iterations: usize,
    /// `"dirichlet"` or `"neumann"` walls.
    pub walls: &'static str,
}

/// The ME766 paper's runs (100 × 100 and 100³ grids; sink φ = −10⁸, boundary φ = 1 for
/// Dirichlet, sink −0.5 for Neumann). Of the 3D runs it says "it took hours".
pub const ME766_RUNS: [Me766Run; 5] = [
    Me766Run {
        problem: 1,
        dimension: 2,
        grid: 100,
        accuracy: 1e-4,
        iterations: 647,
        walls: "dirichlet",
    },
    Me766Run {
        problem: 1,
        dimension: 2,
        grid: 100,
        accuracy: 1e-6,
        iterations: 7485,
        walls: "neumann",
    },
    Me766Run {
        problem: 2,
        dimension: 2,
        grid: 100,
        accuracy: 1e-5,
        iterations: 573,
        walls: "dirichlet",
    },
    Me766Run {
        problem: 2,
        dimension: 3,
        grid: 100,
        accuracy: 1e-5,
        iterations: 1278,
        walls: "dirichlet",
    },
    Me766Run {
        problem: 1,
        dimension: 3,
        grid: 100,
        accuracy: 1e-6,
        iterations: 2138,
        walls: "dirichlet",
    },
];

/// One experiment of Connolly, Burns & Weiss (1990), §5 (Lisp, Gauss–Seidel on a TI
/// Explorer II, integer arithmetic).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConnollyRun {
    /// The paper's figure.
    pub figure: u8,
    /// Grid size (columns × rows).
    pub grid: (usize, usize),
    /// Iterations to a zero-error solution, where given.
    pub iterations: Option<usize>,
    /// Seconds.
    pub seconds: f64,
}

/// Connolly et al. (1990), §5: the maze (Figure 2, 64-bit integers), the obstacle region
/// (Figure 3), and the two complicated domains (Figures 4 and 5, at most 80 bits per node).
pub const CONNOLLY_RUNS: [ConnollyRun; 4] = [
    ConnollyRun {
        figure: 2,
        grid: (55, 44),
        iterations: Some(639),
        seconds: 74.0,
    },
    ConnollyRun {
        figure: 3,
        grid: (30, 41),
        iterations: Some(303),
        seconds: 23.0,
    },
    ConnollyRun {
        figure: 4,
        grid: (50, 50),
        iterations: None,
        seconds: 188.0,
    },
    ConnollyRun {
        figure: 5,
        grid: (70, 70),
        iterations: None,
        seconds: 176.0,
    },
];

/// Kim & Khosla (1992), *Real-Time Obstacle Avoidance Using Harmonic Potential Functions*,
/// §5.1, their setting (50) for the bar-shaped robot: obstacle-1 of their Figure 8 with
/// m = 16 panels numbered clockwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KimKhoslaSetting {
    /// Start of the primary control point `(x₀, y₀)` (m); the bar's angle η₀ = 0.
    pub start: [f64; 2],
    /// The goal `(x_g, y_g)` (m).
    pub goal: [f64; 2],
    /// Strength of the uniform flow U.
    pub uniform_speed: f64,
    /// Strength of the goal sink λ_g.
    pub goal_strength: f64,
    /// Desired outward normal velocity V_i on every panel.
    pub normal_velocity: f64,
    /// The minimum allowable distance δ (m).
    pub delta: f64,
}

/// Kim & Khosla (1992), eq. 50 and the text around it.
pub const KIM_KHOSLA_SETTING_50: KimKhoslaSetting = KimKhoslaSetting {
    start: [1.2, 8.5],
    goal: [8.0, 2.0],
    uniform_speed: 1.0,
    goal_strength: 30.0,
    normal_velocity: 0.5,
    delta: 0.2,
};

/// Kim & Khosla (1992), Table 1: the strengths of the 16 panels of obstacle-1, panel 1 first,
/// in the paper's sign (negative: source).
pub const KIM_KHOSLA_TABLE1: [f64; 16] = [
    -4.955, -8.487, -8.572, -5.077, -1.269, -5.408, 5.457, 4.719, 3.931, 2.626, 2.489, 3.832,
    4.632, 5.390, -5.449, -1.364,
];

/// Kim & Khosla (1992), Table 1's caption: the obstacle strength λ_o of obstacle-1.
pub const KIM_KHOSLA_TABLE1_LAMBDA_O: f64 = -7.503;

/// Kim & Khosla (1992), §5.1: "one stagnation point around (2.5, 6.5)".
pub const KIM_KHOSLA_STAGNATION_POINT: [f64; 2] = [2.5, 6.5];

/// Kim & Khosla (1992), eq. 51 and §5.2, the 3-dof manipulator: end effector from
/// (−2, 8) to the goal (5, 9), base at (−2, 2), U = 1, λ_g = 30, V_i = 1, two rectangles of
/// 12 panels each (their Figure 10), δ = 0.2.
pub const KIM_KHOSLA_SETTING_51: KimKhoslaSetting = KimKhoslaSetting {
    start: [-2.0, 8.0],
    goal: [5.0, 9.0],
    uniform_speed: 1.0,
    goal_strength: 30.0,
    normal_velocity: 1.0,
    delta: 0.2,
};

/// Kim & Khosla (1992), Table 2: the strengths of the 24 panels of obstacle-2 (paper's sign).
pub const KIM_KHOSLA_TABLE2: [f64; 24] = [
    -14.014, -18.239, -20.175, -20.123, -17.267, 0.780, 14.849, 17.990, 18.054, 16.096, 11.748,
    -0.700, -22.325, -28.297, -29.466, -26.807, -20.224, -0.532, 17.999, 24.802, 27.55, 26.386,
    20.479, -2.342,
];

/// Kim & Khosla (1992), Table 2's caption: the lower and upper obstacle strengths.
pub const KIM_KHOSLA_TABLE2_LAMBDA_O: [f64; 2] = [-11.040, -11.332];
