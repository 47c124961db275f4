//! Readers for the MovingAI grid benchmark formats (Sturtevant, *Benchmarks for Grid-Based
//! Pathfinding*, 2012): `.map` grids and version 1 `.scen` scenario lists.
//!
//! A `.map` file is a header of `type octile`, `height H` and `width W` lines (in any order,
//! each once) ended by a `map` line, then `H` lines of `W` characters, the first line being
//! the **top** row of the grid. `.`, `G` and `S` are free; `@`, `O`, `T` and `W` are blocked
//! ([`Cell::Occupied`]); any other character is an error. [`read_map`] turns it into an
//! [`OccupancyMap`] whose row 0 is the file's **last** grid line (the map's bottom), with its
//! origin at `[0, 0, 0]` and cells of the given resolution.
//!
//! A `.scen` file starts with `version 1` (or `version 1.0`); each further non-blank line has
//! nine fields separated by tabs or spaces:
//! `bucket map width height start_x start_y goal_x goal_y optimal_length`. MovingAI counts
//! `y` from the **top** row; [`read_scen`] converts start and goal to this crate's
//! `(column, row from the bottom)` ([`Scenario::start`], [`Scenario::goal`]), ready for
//! [`OccupancyMap::cell_center`].
//!
//! CRLF line endings, a UTF-8 byte-order mark and trailing whitespace are accepted. Every
//! error is a [`MovingAiError`] whose message is one line naming the file and the 1-based
//! line (and column, for a bad terrain character). Nothing here panics on any input, and no
//! more memory is reserved than the text's length warrants, whatever its header claims.
//!
//! ```
//! use harmonic_planner::map::Cell;
//! use harmonic_planner::map::movingai::{read_map, read_scen};
//! let map = read_map("type octile\nheight 2\nwidth 3\nmap\n..@\n.@.\n", "tiny.map", 1.0)?;
//! assert_eq!(map.cell(2, 1), Cell::Occupied); // the file's first grid line is the top row
//! assert_eq!(map.cell(1, 0), Cell::Occupied);
//! let scen = read_scen("version 1\n0\ttiny.map\t3\t2\t0\t0\t2\t1\t2.41421356\n", "tiny.scen")?;
//! scen[0].check_against(&map)?;
//! assert_eq!((scen[0].start, scen[0].goal), ((0, 1), (2, 0))); // rows from the bottom
//! let start = map.cell_center(scen[0].start.0, scen[0].start.1);
//! assert_eq!(start, [0.5, 1.5]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::Path;

use super::{Cell, MAX_MAP_CELLS, MapError, OccupancyMap};

/// What a `.map` header must hold, for messages.
const MAP_HEADER: &str = "a .map header is `type octile`, `height H`, `width W`, then `map`";

/// The nine fields of a version 1 `.scen` line, for messages.
const SCEN_FIELDS: &str = "bucket map width height start_x start_y goal_x goal_y optimal_length";

/// Why a MovingAI `.map` or `.scen` file could not be read. Every message is one line that
/// starts with the file's name and, where one is to blame, its 1-based line.
#[derive(Debug, thiserror::Error)]
pub enum MovingAiError {
    /// The file could not be read.
    #[error("cannot read {file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The resolution asked of [`read_map`] is not a positive finite number.
    #[error(
        "{file}: the resolution must be a positive finite number of metres per cell, got {resolution}"
    )]
    BadResolution {
        /// The `.map` file.
        file: String,
        /// The resolution given.
        resolution: f64,
    },
    /// A header line is not `type T`, `height H`, `width W` or `map`.
    #[error("{file}:{line}: unexpected header line {text:?} ({MAP_HEADER})")]
    HeaderLine {
        /// The `.map` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The line as written (cut after 40 characters).
        text: String,
    },
    /// A header field is given twice.
    #[error("{file}:{line}: `{field}` is given twice in the header")]
    DuplicateField {
        /// The `.map` file.
        file: String,
        /// The line of the second one, from 1.
        line: usize,
        /// `type`, `height` or `width`.
        field: &'static str,
    },
    /// The map type is not `octile`.
    #[error("{file}:{line}: map type {kind:?} is not supported (expected `type octile`)")]
    UnsupportedType {
        /// The `.map` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The type as written (cut after 40 characters).
        kind: String,
    },
    /// The header ends (at its `map` line) without one of its fields.
    #[error("{file}:{line}: the header has no `{field}` line ({MAP_HEADER})")]
    MissingField {
        /// The `.map` file.
        file: String,
        /// The line of `map`, from 1.
        line: usize,
        /// `type`, `height` or `width`.
        field: &'static str,
    },
    /// The file ends before the `map` line that ends the header.
    #[error(
        "{file}:{line}: the file ends before the `map` line that ends the header ({MAP_HEADER})"
    )]
    NoMapLine {
        /// The `.map` file.
        file: String,
        /// The line after the file's last, from 1.
        line: usize,
    },
    /// `height` or `width` is not a whole number above zero.
    #[error("{file}:{line}: `{field}` must be a whole number above 0, got {value:?}")]
    BadSize {
        /// The `.map` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// `height` or `width`.
        field: &'static str,
        /// The value as written (cut after 40 characters).
        value: String,
    },
    /// The header's grid has more than [`MAX_MAP_CELLS`] cells.
    #[error(
        "{file}:{line}: a {width} × {height} map has more than {MAX_MAP_CELLS} cells, the most a map may have"
    )]
    TooLarge {
        /// The `.map` file.
        file: String,
        /// The line of the later of `height` and `width`, from 1.
        line: usize,
        /// The header's width.
        width: usize,
        /// The header's height.
        height: usize,
    },
    /// A grid line is shorter or longer than the header's width.
    #[error("{file}:{line}: the row has {found} cells, expected {expected} (the header's width)")]
    RowLength {
        /// The `.map` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The header's width.
        expected: usize,
        /// The characters on the line (trailing whitespace not counted).
        found: usize,
    },
    /// A grid line holds a character that is no terrain.
    #[error(
        "{file}:{line}: column {column}: unknown terrain character {character:?} (expected . G S free, @ O T W blocked)"
    )]
    BadTerrain {
        /// The `.map` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The column, from 1 (in characters).
        column: usize,
        /// The character.
        character: char,
    },
    /// The file ends before the header's height of grid lines.
    #[error(
        "{file}:{line}: the file ends after {found} rows, expected {expected} (the header's height)"
    )]
    TooFewRows {
        /// The `.map` file.
        file: String,
        /// The line after the file's last, from 1.
        line: usize,
        /// The header's height.
        expected: usize,
        /// The grid lines read.
        found: usize,
    },
    /// A non-blank line follows the header's height of grid lines.
    #[error("{file}:{line}: more rows than the header's height {expected}")]
    TooManyRows {
        /// The `.map` file.
        file: String,
        /// The first extra line, from 1.
        line: usize,
        /// The header's height.
        expected: usize,
    },
    /// The grid read could not be made a map (not expected: the reader checks what
    /// [`OccupancyMap::from_cells`] does).
    #[error("{file}: {source}")]
    Map {
        /// The `.map` file.
        file: String,
        /// What the map refused (boxed: the map's errors are large).
        #[source]
        source: Box<MapError>,
    },
    /// The `.scen` file does not start with a `version` line (version 0 files, which have
    /// none, are not supported).
    #[error("{file}:{line}: expected `version 1` as the first line of a scenario file")]
    MissingVersion {
        /// The `.scen` file.
        file: String,
        /// The first non-blank line, or the line after the file's last, from 1.
        line: usize,
    },
    /// The `.scen` file's version is not 1.
    #[error("{file}:{line}: scenario version {version:?} is not supported (expected `version 1`)")]
    UnsupportedVersion {
        /// The `.scen` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The version as written (cut after 40 characters).
        version: String,
    },
    /// A scenario line does not have nine fields.
    #[error("{file}:{line}: expected 9 fields ({SCEN_FIELDS}), found {found}")]
    FieldCount {
        /// The `.scen` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The fields on the line.
        found: usize,
    },
    /// A scenario field does not parse.
    #[error("{file}:{line}: field `{field}` must be {expected}, got {value:?}")]
    BadField {
        /// The `.scen` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The field's name (`bucket`, `width`, `start_x`, `optimal_length`, ...).
        field: &'static str,
        /// What the field must be.
        expected: &'static str,
        /// The value as written (cut after 40 characters).
        value: String,
    },
    /// The optimal length is negative, infinite or not a number.
    #[error("{file}:{line}: the optimal length must be finite and at least 0, got {value}")]
    BadOptimal {
        /// The `.scen` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The length.
        value: f64,
    },
    /// A start or goal is off the map size its own line gives.
    #[error(
        "{file}:{line}: {point} ({x}, {y}) is outside the {width} × {height} map the line names"
    )]
    OffScenarioMap {
        /// The `.scen` file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// `start` or `goal`.
        point: &'static str,
        /// Its column, as written.
        x: usize,
        /// Its row from the top, as written.
        y: usize,
        /// The line's map width.
        width: usize,
        /// The line's map height.
        height: usize,
    },
    /// A scenario's map size is not that of the map it is checked against
    /// ([`Scenario::check_against`]).
    #[error(
        "a scenario on {map} expects a {width} × {height} map, but {source_name} is {map_width} × {map_height}"
    )]
    SizeMismatch {
        /// The scenario's map name.
        map: String,
        /// The scenario's width.
        width: usize,
        /// The scenario's height.
        height: usize,
        /// The map's source (its file, or `map`).
        source_name: String,
        /// The map's width.
        map_width: usize,
        /// The map's height.
        map_height: usize,
    },
    /// A scenario's start or goal is not a cell of the map it is checked against
    /// ([`Scenario::check_against`]).
    #[error(
        "a scenario on {map}: its {point} cell (column {column}, row {row} from the bottom) is outside {source_name}, which is {width} × {height}"
    )]
    CellOffMap {
        /// The scenario's map name.
        map: String,
        /// `start` or `goal`.
        point: &'static str,
        /// The cell's column.
        column: usize,
        /// The cell's row, from the bottom.
        row: usize,
        /// The map's source (its file, or `map`).
        source_name: String,
        /// The map's width.
        width: usize,
        /// The map's height.
        height: usize,
    },
}

/// One problem of a `.scen` file: a start and a goal on a named map, with the length of the
/// shortest octile path between them.
///
/// `start` and `goal` are `(column, row)` with **row 0 at the bottom**, as
/// [`OccupancyMap::cell`] and [`OccupancyMap::cell_center`] take them: the file's
/// `(x, y)`, whose `y` counts from the top, becomes `(x, height - 1 - y)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// The bucket (problems of similar length share one).
    pub bucket: u32,
    /// The map's file name, as written (usually relative to the benchmark's map folder).
    pub map: String,
    /// The map's width in cells.
    pub width: usize,
    /// The map's height in cells.
    pub height: usize,
    /// The start cell: `(column, row from the bottom)`.
    pub start: (usize, usize),
    /// The goal cell: `(column, row from the bottom)`.
    pub goal: (usize, usize),
    /// The length of the shortest 8-connected path (straight steps 1, diagonal steps √2, no
    /// corner cutting), in cells.
    pub optimal: f64,
}

impl Scenario {
    /// Checks that the scenario fits `map`: the same width and height, and start and goal
    /// among its cells. Whether those cells are free is not checked.
    pub fn check_against(&self, map: &OccupancyMap) -> Result<(), MovingAiError> {
        let (width, height) = (map.width(), map.height());
        if (self.width, self.height) != (width, height) {
            return Err(MovingAiError::SizeMismatch {
                map: self.map.clone(),
                width: self.width,
                height: self.height,
                source_name: map.source.clone(),
                map_width: width,
                map_height: height,
            });
        }
        for (point, (column, row)) in [("start", self.start), ("goal", self.goal)] {
            if column >= width || row >= height {
                return Err(MovingAiError::CellOffMap {
                    map: self.map.clone(),
                    point,
                    column,
                    row,
                    source_name: map.source.clone(),
                    width,
                    height,
                });
            }
        }
        Ok(())
    }
}

/// The lines of a text, numbered from 1, without their line ending or trailing whitespace
/// (and without a leading byte-order mark).
struct Lines<'a> {
    inner: std::str::Lines<'a>,
    /// The number of the last line returned (0 before the first).
    line: usize,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        Lines {
            inner: text.lines(),
            line: 0,
        }
    }

    /// The number of the line after the last one read (the end of file, once all are read).
    fn next_line(&self) -> usize {
        self.line + 1
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<Self::Item> {
        let text = self.inner.next()?;
        self.line += 1;
        Some((self.line, text.trim_end()))
    }
}

/// `s`, cut after 40 characters (for messages).
fn shown(s: &str) -> String {
    let mut t: String = s.chars().take(40).collect();
    if s.chars().nth(40).is_some() {
        t.push('…');
    }
    t
}

/// Reads a file as text, replacing bytes that are not UTF-8 (so that they are reported where
/// they stand, as unknown characters).
fn read_text(path: &Path) -> Result<(String, String), MovingAiError> {
    let file = path.display().to_string();
    match std::fs::read(path) {
        Ok(bytes) => Ok((String::from_utf8_lossy(&bytes).into_owned(), file)),
        Err(source) => Err(MovingAiError::Io { file, source }),
    }
}

/// Reads a MovingAI `.map` file (see the [module documentation](self)) into a map of cells
/// `resolution` metres wide with its origin at `[0, 0, 0]`; its source in messages is the
/// path as given.
pub fn load_map(path: impl AsRef<Path>, resolution: f64) -> Result<OccupancyMap, MovingAiError> {
    let (text, file) = read_text(path.as_ref())?;
    read_map(&text, &file, resolution)
}

/// Reads the text of a MovingAI `.map` file (see the [module documentation](self)) into a map
/// of cells `resolution` metres wide with its origin at `[0, 0, 0]`, the file's first grid
/// line becoming the map's top row. `name` stands for the file in messages and becomes the
/// map's source.
pub fn read_map(text: &str, name: &str, resolution: f64) -> Result<OccupancyMap, MovingAiError> {
    let file = || name.to_string();
    if !(resolution.is_finite() && resolution > 0.0) {
        return Err(MovingAiError::BadResolution {
            file: file(),
            resolution,
        });
    }
    let mut lines = Lines::new(text);

    // The header: `type`, `height`, `width` in any order (each once), then `map`.
    let mut kind = None;
    let mut height = None;
    let mut width = None;
    let map_line = loop {
        let Some((line, text)) = lines.next() else {
            return Err(MovingAiError::NoMapLine {
                file: file(),
                line: lines.next_line(),
            });
        };
        let mut tokens = text.split_whitespace();
        let (Some(key), value, extra) = (tokens.next(), tokens.next(), tokens.next()) else {
            continue; // a blank line
        };
        let header_line = || MovingAiError::HeaderLine {
            file: file(),
            line,
            text: shown(text),
        };
        let (Some(value), None) = (value, extra) else {
            if key == "map" && value.is_none() {
                break line;
            }
            return Err(header_line());
        };
        let (field, slot) = match key {
            "type" => {
                if kind.replace(line).is_some() {
                    return Err(MovingAiError::DuplicateField {
                        file: file(),
                        line,
                        field: "type",
                    });
                }
                if value != "octile" {
                    return Err(MovingAiError::UnsupportedType {
                        file: file(),
                        line,
                        kind: shown(value),
                    });
                }
                continue;
            }
            "height" => ("height", &mut height),
            "width" => ("width", &mut width),
            _ => return Err(header_line()),
        };
        if slot.is_some() {
            return Err(MovingAiError::DuplicateField {
                file: file(),
                line,
                field,
            });
        }
        match value.parse::<usize>() {
            Ok(n) if n > 0 => *slot = Some((line, n)),
            _ => {
                return Err(MovingAiError::BadSize {
                    file: file(),
                    line,
                    field,
                    value: shown(value),
                });
            }
        }
    };
    let missing = |field| MovingAiError::MissingField {
        file: file(),
        line: map_line,
        field,
    };
    if kind.is_none() {
        return Err(missing("type"));
    }
    let (height_line, h) = height.ok_or_else(|| missing("height"))?;
    let (width_line, w) = width.ok_or_else(|| missing("width"))?;
    let Some(n) = w.checked_mul(h).filter(|&n| n <= MAX_MAP_CELLS) else {
        return Err(MovingAiError::TooLarge {
            file: file(),
            line: height_line.max(width_line),
            width: w,
            height: h,
        });
    };

    // The grid, top row first; every cell takes at least a byte of the text, so the text's
    // length bounds what is reserved whatever the header says.
    let mut cells = Vec::with_capacity(n.min(text.len()));
    for rows in 0..h {
        let Some((line, row)) = lines.next() else {
            return Err(MovingAiError::TooFewRows {
                file: file(),
                line: lines.next_line(),
                expected: h,
                found: rows,
            });
        };
        let mut found = 0;
        for (column, character) in row.chars().enumerate() {
            if column == w {
                return Err(MovingAiError::RowLength {
                    file: file(),
                    line,
                    expected: w,
                    found: row.chars().count(),
                });
            }
            cells.push(match character {
                '.' | 'G' | 'S' => Cell::Free,
                '@' | 'O' | 'T' | 'W' => Cell::Occupied,
                _ => {
                    return Err(MovingAiError::BadTerrain {
                        file: file(),
                        line,
                        column: column + 1,
                        character,
                    });
                }
            });
            found = column + 1;
        }
        if found < w {
            return Err(MovingAiError::RowLength {
                file: file(),
                line,
                expected: w,
                found,
            });
        }
    }
    if let Some((line, _)) = lines.find(|(_, text)| !text.is_empty()) {
        return Err(MovingAiError::TooManyRows {
            file: file(),
            line,
            expected: h,
        });
    }

    // Row 0 at the bottom: swap the rows end for end.
    for top in 0..h / 2 {
        let bottom = h - 1 - top;
        let (upper, lower) = cells.split_at_mut(bottom * w);
        upper[top * w..(top + 1) * w].swap_with_slice(&mut lower[..w]);
    }
    let mut map =
        OccupancyMap::from_cells(w, h, resolution, [0.0; 3], cells).map_err(|source| {
            MovingAiError::Map {
                file: file(),
                source: Box::new(source),
            }
        })?;
    map.source = file();
    Ok(map)
}

/// Reads a version 1 MovingAI `.scen` file (see [`read_scen`]); its source in messages is the
/// path as given.
pub fn load_scen(path: impl AsRef<Path>) -> Result<Vec<Scenario>, MovingAiError> {
    let (text, file) = read_text(path.as_ref())?;
    read_scen(&text, &file)
}

/// Reads the text of a version 1 MovingAI `.scen` file: a `version 1` (or `version 1.0`)
/// line, then one scenario a line, nine fields separated by tabs or spaces (see the
/// [module documentation](self)); blank lines are skipped. The file's `y`, counted from the
/// top row, is converted to a row from the bottom (see [`Scenario`]), so start and goal
/// must lie on the map size their line gives. `name` stands for the file in messages.
///
/// A line split by tabs into nine non-empty fields keeps spaces inside its fields (a map
/// name with a space); any other line is split at every run of whitespace.
pub fn read_scen(text: &str, name: &str) -> Result<Vec<Scenario>, MovingAiError> {
    let file = || name.to_string();
    let mut lines = Lines::new(text);
    let Some((line, first)) = lines.find(|(_, text)| !text.is_empty()) else {
        return Err(MovingAiError::MissingVersion {
            file: file(),
            line: lines.next_line(),
        });
    };
    let version = first.trim_start().strip_prefix("version");
    let Some(version) = version.filter(|v| v.is_empty() || v.starts_with(char::is_whitespace))
    else {
        return Err(MovingAiError::MissingVersion { file: file(), line });
    };
    let version = version.trim();
    if version != "1" && version != "1.0" {
        return Err(MovingAiError::UnsupportedVersion {
            file: file(),
            line,
            version: shown(version),
        });
    }

    let mut scenarios = Vec::new();
    for (line, text) in lines {
        if text.trim_start().is_empty() {
            continue;
        }
        let tabbed: Vec<&str> = text.split('\t').map(str::trim).collect();
        let fields = if tabbed.len() == 9 && tabbed.iter().all(|f| !f.is_empty()) {
            tabbed
        } else {
            text.split_whitespace().collect()
        };
        let [bucket, map, width, height, sx, sy, gx, gy, optimal] = fields[..] else {
            return Err(MovingAiError::FieldCount {
                file: file(),
                line,
                found: fields.len(),
            });
        };
        let bad = |field, expected, value: &str| MovingAiError::BadField {
            file: file(),
            line,
            field,
            expected,
            value: shown(value),
        };
        let whole = |field, value: &str| {
            value
                .parse::<usize>()
                .map_err(|_| bad(field, "a whole number, 0 or more", value))
        };
        let bucket = bucket
            .parse::<u32>()
            .map_err(|_| bad("bucket", "a whole number, 0 or more", bucket))?;
        let (width, height) = (whole("width", width)?, whole("height", height)?);
        let start = (whole("start_x", sx)?, whole("start_y", sy)?);
        let goal = (whole("goal_x", gx)?, whole("goal_y", gy)?);
        let length = optimal
            .parse::<f64>()
            .map_err(|_| bad("optimal_length", "a number", optimal))?;
        if !(length.is_finite() && length >= 0.0) {
            return Err(MovingAiError::BadOptimal {
                file: file(),
                line,
                value: length,
            });
        }
        let from_bottom = |point, (x, y): (usize, usize)| {
            if x < width && y < height {
                Ok((x, height - 1 - y))
            } else {
                Err(MovingAiError::OffScenarioMap {
                    file: file(),
                    line,
                    point,
                    x,
                    y,
                    width,
                    height,
                })
            }
        };
        let start = from_bottom("start", start)?;
        let goal = from_bottom("goal", goal)?;
        scenarios.push(Scenario {
            bucket,
            map: map.to_string(),
            width,
            height,
            start,
            goal,
            optimal: length,
        });
    }
    Ok(scenarios)
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_fixtures::Rng;

    const MAZE: &str = "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@T\nS.OW\n";

    const SCEN: &str = "version 1\n\
        0\tmaze.map\t4\t3\t1\t0\t0\t2\t3.41421356\n\
        \n\
        1 maze.map 4 3 3 0 1 2 2.82842712\n";

    fn map_err(text: &str) -> String {
        match read_map(text, "maze.map", 1.0) {
            Ok(_) => panic!("accepted {text:?}"),
            Err(e) => e.to_string(),
        }
    }

    fn scen_err(text: &str) -> String {
        match read_scen(text, "maze.scen") {
            Ok(s) => panic!("accepted {text:?}: {s:?}"),
            Err(e) => e.to_string(),
        }
    }

    fn assert_cells(map: &OccupancyMap, top_first: &[&str]) {
        assert_eq!(map.height(), top_first.len());
        for (k, row) in top_first.iter().enumerate() {
            let j = map.height() - 1 - k;
            let read: String = (0..map.width())
                .map(|i| match map.cell(i, j) {
                    Cell::Free => '.',
                    Cell::Occupied => '@',
                    Cell::Unknown => '?',
                })
                .collect();
            assert_eq!(read, *row, "row {j} from the bottom");
        }
    }

    #[test]
    fn a_small_map_parses_with_its_top_row_highest() {
        let map = read_map(MAZE, "maze.map", 0.5).expect("valid map");
        assert_eq!((map.width(), map.height()), (4, 3));
        assert_eq!(map.resolution(), 0.5);
        assert_eq!(map.origin(), [0.0; 3]);
        assert_eq!(map.source, "maze.map");
        // The file's first grid line `@...` is row 2, its last `S.OW` row 0.
        assert_eq!(map.cell(0, 2), Cell::Occupied);
        assert_eq!(map.cell(1, 2), Cell::Free);
        assert_eq!(map.cell(2, 1), Cell::Occupied);
        assert_eq!(map.cell(3, 1), Cell::Occupied);
        assert_eq!(map.cell(1, 1), Cell::Free);
        assert_cells(&map, &["@...", "..@@", "..@@"]);
        assert_eq!(map.cell_center(0, 2), [0.25, 1.25]);

        // CRLF, trailing whitespace, a byte-order mark, blank header lines and another
        // header order read the same.
        let crlf = "\u{feff}type octile \r\n\r\nwidth 4\r\nheight\t3\r\nmap\r\n@... \r\n.G@T\t\r\nS.OW\r\n\r\n  \r\n";
        let other = read_map(crlf, "maze.map", 0.5).expect("CRLF map");
        assert_cells(&other, &["@...", "..@@", "..@@"]);

        // One row, and an even number of rows, flip too.
        let one = read_map("type octile\nheight 1\nwidth 2\nmap\n.@", "one.map", 1.0).unwrap();
        assert_cells(&one, &[".@"]);
        let four = "type octile\nheight 4\nwidth 1\nmap\n@\n.\n.\nT\n";
        assert_cells(
            &read_map(four, "four.map", 1.0).unwrap(),
            &["@", ".", ".", "@"],
        );
    }

    #[test]
    fn every_map_error_names_file_line_and_column() {
        let cases: &[(&str, &str)] = &[
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@T\nS.Ox\n",
                "maze.map:7: column 4: unknown terrain character 'x' (expected . G S free, @ O T W blocked)",
            ),
            (
                "type octile\nheight 1\nwidth 3\nmap\n.\t.\n",
                "maze.map:5: column 2: unknown terrain character '\\t' (expected . G S free, @ O T W blocked)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@\nS.OW\n",
                "maze.map:6: the row has 3 cells, expected 4 (the header's width)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@T.@\nS.OW\n",
                "maze.map:6: the row has 6 cells, expected 4 (the header's width)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n\nS.OW\n",
                "maze.map:6: the row has 0 cells, expected 4 (the header's width)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@T\n",
                "maze.map:7: the file ends after 2 rows, expected 3 (the header's height)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap\n@...\n.G@T\nS.OW\n....\n",
                "maze.map:8: more rows than the header's height 3",
            ),
            (
                "type octile\nwidth 4\nmap\n@...\n",
                "maze.map:3: the header has no `height` line (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "type octile\nheight 3\nmap\n",
                "maze.map:3: the header has no `width` line (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "height 3\nwidth 4\nmap\n",
                "maze.map:3: the header has no `type` line (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "type octile\nheight 3\nwidth 4\n",
                "maze.map:4: the file ends before the `map` line that ends the header (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "",
                "maze.map:1: the file ends before the `map` line that ends the header (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "type octile\nheight three\nwidth 4\nmap\n",
                "maze.map:2: `height` must be a whole number above 0, got \"three\"",
            ),
            (
                "type octile\nheight 3\nwidth 0\nmap\n",
                "maze.map:3: `width` must be a whole number above 0, got \"0\"",
            ),
            (
                "type octile\nheight -3\nwidth 4\nmap\n",
                "maze.map:2: `height` must be a whole number above 0, got \"-3\"",
            ),
            (
                "type octile\nheight 16385\nwidth 16384\nmap\n",
                "maze.map:3: a 16384 × 16385 map has more than 268435456 cells, the most a map may have",
            ),
            (
                "type octile\nwidth 2\nheight 18446744073709551615\nmap\n",
                "maze.map:3: a 2 × 18446744073709551615 map has more than 268435456 cells, the most a map may have",
            ),
            (
                "type octile\nheight 3\nheight 3\nwidth 4\nmap\n",
                "maze.map:3: `height` is given twice in the header",
            ),
            (
                "type octile\ntype octile\nheight 3\nwidth 4\nmap\n",
                "maze.map:2: `type` is given twice in the header",
            ),
            (
                "type hex\nheight 3\nwidth 4\nmap\n",
                "maze.map:1: map type \"hex\" is not supported (expected `type octile`)",
            ),
            (
                "type octile\nheight 3 4\nwidth 4\nmap\n",
                "maze.map:2: unexpected header line \"height 3 4\" (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "type octile\nheight 3\nwidth 4\nmap please\n",
                "maze.map:4: unexpected header line \"map please\" (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
            (
                "@...\n",
                "maze.map:1: unexpected header line \"@...\" (a .map header is `type octile`, `height H`, `width W`, then `map`)",
            ),
        ];
        for (text, message) in cases {
            assert_eq!(map_err(text), *message, "for {text:?}");
        }
        // The largest map allowed is not refused for its size, and nothing of its size is
        // reserved before its rows are read.
        assert_eq!(
            map_err("type octile\nheight 16384\nwidth 16384\nmap\n.\n"),
            "maze.map:5: the row has 1 cells, expected 16384 (the header's width)"
        );
        let e = read_map(MAZE, "maze.map", 0.0).unwrap_err().to_string();
        assert_eq!(
            e,
            "maze.map: the resolution must be a positive finite number of metres per cell, got 0"
        );
        assert!(read_map(MAZE, "maze.map", f64::NAN).is_err());
        let e = load_map("/nonexistent/dir/maze.map", 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("cannot read /nonexistent/dir/maze.map: "),
            "{e}"
        );
    }

    #[test]
    fn scenarios_parse_and_convert_to_rows_from_the_bottom() {
        let map = read_map(MAZE, "maze.map", 1.0).unwrap();
        let scen = read_scen(SCEN, "maze.scen").expect("valid scenarios");
        assert_eq!(scen.len(), 2);
        assert_eq!(
            scen[0],
            Scenario {
                bucket: 0,
                map: "maze.map".into(),
                width: 4,
                height: 3,
                start: (1, 2),
                goal: (0, 0),
                optimal: 3.41421356,
            }
        );
        assert_eq!(
            (scen[1].bucket, scen[1].start, scen[1].goal),
            (1, (3, 2), (1, 0))
        );
        for s in &scen {
            s.check_against(&map).expect("fits");
            assert_eq!(map.cell(s.start.0, s.start.1), Cell::Free);
            assert_eq!(map.cell(s.goal.0, s.goal.1), Cell::Free);
        }
        // `version 1.0`, CRLF, leading blank lines, a map name with a space between tabs.
        let other = "\r\nversion 1.0\r\n3\tmy maze.map\t4\t3\t1\t0\t0\t2\t3.5\r\n";
        let s = read_scen(other, "maze.scen").unwrap();
        assert_eq!((s[0].map.as_str(), s[0].start), ("my maze.map", (1, 2)));
        assert!(read_scen("version 1\n", "empty.scen").unwrap().is_empty());
    }

    #[test]
    fn every_scenario_error_names_file_and_line() {
        let cases: &[(&str, &str)] = &[
            (
                "",
                "maze.scen:1: expected `version 1` as the first line of a scenario file",
            ),
            (
                "0 maze.map 4 3 1 0 0 2 3.4\n",
                "maze.scen:1: expected `version 1` as the first line of a scenario file",
            ),
            (
                "\nversion 2\n",
                "maze.scen:2: scenario version \"2\" is not supported (expected `version 1`)",
            ),
            (
                "version1\n",
                "maze.scen:1: expected `version 1` as the first line of a scenario file",
            ),
            (
                "version\n",
                "maze.scen:1: scenario version \"\" is not supported (expected `version 1`)",
            ),
            (
                "version 1\n\n0 maze.map 4 3 1 0 0 2\n",
                "maze.scen:3: expected 9 fields (bucket map width height start_x start_y goal_x goal_y optimal_length), found 8",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 2 3.4 7\n",
                "maze.scen:2: expected 9 fields (bucket map width height start_x start_y goal_x goal_y optimal_length), found 10",
            ),
            (
                "version 1\n0 maze.map 4 3 one 0 0 2 3.4\n",
                "maze.scen:2: field `start_x` must be a whole number, 0 or more, got \"one\"",
            ),
            (
                "version 1\n0 maze.map 4 3 1 -1 0 2 3.4\n",
                "maze.scen:2: field `start_y` must be a whole number, 0 or more, got \"-1\"",
            ),
            (
                "version 1\n-2 maze.map 4 3 1 0 0 2 3.4\n",
                "maze.scen:2: field `bucket` must be a whole number, 0 or more, got \"-2\"",
            ),
            (
                "version 1\n0 maze.map 4.5 3 1 0 0 2 3.4\n",
                "maze.scen:2: field `width` must be a whole number, 0 or more, got \"4.5\"",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 2 far\n",
                "maze.scen:2: field `optimal_length` must be a number, got \"far\"",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 2 -3.4\n",
                "maze.scen:2: the optimal length must be finite and at least 0, got -3.4",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 2 inf\n",
                "maze.scen:2: the optimal length must be finite and at least 0, got inf",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 2 NaN\n",
                "maze.scen:2: the optimal length must be finite and at least 0, got NaN",
            ),
            (
                "version 1\n0 maze.map 4 3 1 0 0 3 3.4\n",
                "maze.scen:2: goal (0, 3) is outside the 4 × 3 map the line names",
            ),
            (
                "version 1\n0 maze.map 4 3 4 0 0 2 3.4\n",
                "maze.scen:2: start (4, 0) is outside the 4 × 3 map the line names",
            ),
        ];
        for (text, message) in cases {
            assert_eq!(scen_err(text), *message, "for {text:?}");
        }

        let map = read_map(MAZE, "maze.map", 1.0).unwrap();
        let wide = read_scen("version 1\n0 maze.map 5 3 1 0 0 2 3.4\n", "s").unwrap();
        assert_eq!(
            wide[0].check_against(&map).unwrap_err().to_string(),
            "a scenario on maze.map expects a 5 × 3 map, but maze.map is 4 × 3"
        );
        let off = Scenario {
            goal: (0, 3),
            ..read_scen(SCEN, "maze.scen").unwrap()[0].clone()
        };
        assert_eq!(
            off.check_against(&map).unwrap_err().to_string(),
            "a scenario on maze.map: its goal cell (column 0, row 3 from the bottom) is outside maze.map, which is 4 × 3"
        );
        let e = load_scen("/nonexistent/dir/maze.scen")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("cannot read /nonexistent/dir/maze.scen: "),
            "{e}"
        );
    }

    #[test]
    fn files_load_from_disk() {
        let dir = std::env::temp_dir().join(format!("movingai-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (map_path, scen_path) = (dir.join("maze.map"), dir.join("maze.map.scen"));
        std::fs::write(&map_path, MAZE).unwrap();
        std::fs::write(&scen_path, SCEN).unwrap();
        let map = load_map(&map_path, 1.0).unwrap();
        let scen = load_scen(&scen_path).unwrap();
        scen[0].check_against(&map).unwrap();
        // A byte that is not UTF-8 is reported where it stands.
        std::fs::write(&map_path, b"type octile\nheight 1\nwidth 2\nmap\n.\xff\n").unwrap();
        let e = load_map(&map_path, 1.0).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{}:5: column 2: unknown terrain character '\u{fffd}' (expected . G S free, @ O T W blocked)",
                map_path.display()
            )
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A random edit of `text`: a character replaced, inserted or deleted, a line deleted
    /// or doubled, or a number replaced by an awkward one.
    fn mutate(text: &str, rng: &mut Rng) -> String {
        const CHARS: &[char] = &[
            '.', '@', 'G', 'S', 'O', 'T', 'W', 'x', ' ', '\t', '\n', '\r', '0', '1', '9', '-', '.',
            'e', 'é', '\u{feff}', '\0',
        ];
        const NUMBERS: &[&str] = &[
            "0",
            "1",
            "-1",
            "16384",
            "16385",
            "268435456",
            "18446744073709551615",
            "99999999999999999999999",
            "1e3",
            "nan",
            "inf",
            "-0",
            "",
        ];
        let mut chars: Vec<char> = text.chars().collect();
        for _ in 0..1 + rng.below(3) {
            let at = rng.below(chars.len() + 1);
            match rng.below(6) {
                0 if at < chars.len() => chars[at] = CHARS[rng.below(CHARS.len())],
                1 => chars.insert(at, CHARS[rng.below(CHARS.len())]),
                2 if at < chars.len() => {
                    chars.remove(at);
                }
                3 | 4 => {
                    // A line deleted (3) or doubled (4).
                    let start = chars[..at]
                        .iter()
                        .rposition(|&c| c == '\n')
                        .map_or(0, |k| k + 1);
                    let end = chars[at..]
                        .iter()
                        .position(|&c| c == '\n')
                        .map_or(chars.len(), |k| at + k + 1);
                    let line: Vec<char> = chars[start..end].to_vec();
                    if rng.below(2) == 0 || line.is_empty() {
                        chars.drain(start..end);
                    } else {
                        chars.splice(start..start, line);
                    }
                }
                _ => {
                    // The run of digits around `at` replaced by an awkward number.
                    let digit = |c: &char| c.is_ascii_digit() || *c == '.';
                    let start = chars[..at]
                        .iter()
                        .rposition(|c| !digit(c))
                        .map_or(0, |k| k + 1);
                    let end = chars[at..]
                        .iter()
                        .position(|c| !digit(c))
                        .map_or(chars.len(), |k| at + k);
                    let number = NUMBERS[rng.below(NUMBERS.len())];
                    chars.splice(start..end, number.chars());
                }
            }
        }
        chars.into_iter().collect()
    }

    #[test]
    fn random_mutations_never_panic_and_errors_stay_one_line() {
        let mut rng = Rng(0x5eed_0fa1_b0a7);
        let (mut maps_ok, mut scens_ok) = (0, 0);
        // A larger map too, whose grid most edits land in.
        let rows: Vec<String> = (0..8)
            .map(|_| {
                (0..12)
                    .map(|_| ['.', '@', 'G', 'T'][rng.below(4)])
                    .collect()
            })
            .collect();
        let big = format!(
            "type octile\nheight 8\nwidth 12\nmap\n{}\n",
            rows.join("\n")
        );
        for k in 0..4_000 {
            let text = mutate(if k % 2 == 0 { MAZE } else { &big }, &mut rng);
            match read_map(&text, "maze.map", 1.0) {
                Ok(map) => {
                    maps_ok += 1;
                    assert!(map.width() * map.height() <= MAX_MAP_CELLS);
                    // What was read writes back to a file that reads the same.
                    let rows: Vec<String> = (0..map.height())
                        .rev()
                        .map(|j| {
                            (0..map.width())
                                .map(|i| {
                                    if map.cell(i, j) == Cell::Free {
                                        '.'
                                    } else {
                                        '@'
                                    }
                                })
                                .collect()
                        })
                        .collect();
                    let again = format!(
                        "type octile\nheight {}\nwidth {}\nmap\n{}\n",
                        map.height(),
                        map.width(),
                        rows.join("\n")
                    );
                    let again = read_map(&again, "again.map", 1.0).expect("rewritten map");
                    let refs: Vec<&str> = rows.iter().map(String::as_str).collect();
                    assert_cells(&again, &refs);
                }
                Err(e) => {
                    let m = e.to_string();
                    assert!(m.starts_with("maze.map:"), "{m} for {text:?}");
                    assert!(!m.contains('\n') && !m.contains('\r'), "{m:?}");
                }
            }
            let text = mutate(SCEN, &mut rng);
            match read_scen(&text, "maze.scen") {
                Ok(list) => {
                    scens_ok += 1;
                    for s in list {
                        assert!(s.start.0 < s.width && s.start.1 < s.height, "{s:?}");
                        assert!(s.goal.0 < s.width && s.goal.1 < s.height, "{s:?}");
                        assert!(s.optimal.is_finite() && s.optimal >= 0.0);
                    }
                }
                Err(e) => {
                    let m = e.to_string();
                    assert!(m.starts_with("maze.scen:"), "{m} for {text:?}");
                    assert!(!m.contains('\n') && !m.contains('\r'), "{m:?}");
                }
            }
        }
        // Both kinds of outcome are exercised.
        assert!((100..3_900).contains(&maps_ok), "{maps_ok} maps read");
        assert!(
            (100..3_900).contains(&scens_ok),
            "{scens_ok} scenario files read"
        );
    }
}
