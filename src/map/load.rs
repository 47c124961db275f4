//! Reading a map: the map_server YAML and its image (or cells given in memory), the cells'
//! classes and graded costs, and the costs as a conductivity.

use super::*;

fn field<'a>(doc: &'a Value, file: &str, name: &'static str) -> Result<&'a Value, MapError> {
    doc.get(name).ok_or_else(|| MapError::MissingField {
        file: file.to_string(),
        field: name,
    })
}

fn bad(file: &str, field: &'static str, message: String) -> MapError {
    MapError::BadField {
        file: file.to_string(),
        field,
        message,
    }
}

fn number(v: &Value, file: &str, name: &'static str) -> Result<f64, MapError> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| bad(file, name, format!("expected a finite number, got {v:?}")))
}

/// The map_server header of a map.
pub(super) struct Header {
    image: PathBuf,
    resolution: f64,
    origin: [f64; 3],
    occupied_thresh: f64,
    free_thresh: f64,
    negate: bool,
    mode: Mode,
}

fn parse_header(text: &str, file: &str, dir: &Path) -> Result<Header, MapError> {
    let doc: Value = serde_yaml_ng::from_str(text).map_err(|e| MapError::Yaml {
        file: file.to_string(),
        message: e.to_string(),
    })?;
    if !doc.is_mapping() {
        return Err(MapError::Yaml {
            file: file.to_string(),
            message: "expected a mapping of fields (image, resolution, origin, ...)".into(),
        });
    }
    let image = field(&doc, file, "image")?;
    let image = image.as_str().filter(|s| !s.is_empty()).ok_or_else(|| {
        bad(
            file,
            "image",
            format!("expected a file name, got {image:?}"),
        )
    })?;
    let resolution = number(field(&doc, file, "resolution")?, file, "resolution")?;
    if resolution <= 0.0 {
        return Err(bad(
            file,
            "resolution",
            format!("must be positive (metres per cell), got {resolution}"),
        ));
    }
    let origin_v = field(&doc, file, "origin")?;
    let origin_seq = origin_v
        .as_sequence()
        .filter(|s| s.len() == 3 || s.len() == 2)
        .ok_or_else(|| {
            bad(
                file,
                "origin",
                format!("expected [x, y, yaw], got {origin_v:?}"),
            )
        })?;
    let mut origin = [0.0; 3];
    for (o, v) in origin.iter_mut().zip(origin_seq) {
        *o = number(v, file, "origin")?;
    }
    let thresh = |name: &'static str, default: f64| -> Result<f64, MapError> {
        match doc.get(name) {
            None => Ok(default),
            Some(v) => {
                let t = number(v, file, name)?;
                if (0.0..=1.0).contains(&t) {
                    Ok(t)
                } else {
                    Err(bad(file, name, format!("must be between 0 and 1, got {t}")))
                }
            }
        }
    };
    let occupied_thresh = thresh("occupied_thresh", 0.65)?;
    let free_thresh = thresh("free_thresh", 0.196)?;
    if free_thresh > occupied_thresh {
        return Err(bad(
            file,
            "free_thresh",
            format!("{free_thresh} is above occupied_thresh {occupied_thresh}"),
        ));
    }
    let negate = match doc.get("negate") {
        None => false,
        Some(v) => match (v.as_bool(), v.as_i64()) {
            (Some(b), _) => b,
            (None, Some(0)) => false,
            (None, Some(1)) => true,
            _ => return Err(bad(file, "negate", format!("expected 0 or 1, got {v:?}"))),
        },
    };
    let mode = match doc.get("mode") {
        None => Mode::Trinary,
        Some(v) => match v.as_str() {
            Some("trinary") => Mode::Trinary,
            Some("scale") => Mode::Scale,
            Some("raw") => Mode::Raw,
            Some(other) => {
                return Err(MapError::UnsupportedMode {
                    file: file.to_string(),
                    mode: other.to_string(),
                });
            }
            None => return Err(bad(file, "mode", format!("expected a name, got {v:?}"))),
        },
    };
    Ok(Header {
        image: dir.join(image),
        resolution,
        origin,
        occupied_thresh,
        free_thresh,
        negate,
        mode,
    })
}

/// The map_server rule for one pixel, from the average of its colour channels (0..=255):
/// the cell, and its graded cost. In `scale` and `raw` modes a value between the thresholds
/// is a free cell with a cost rising from 1 at the free threshold to 252 at the occupied one
/// (as Nav2's static layer reads such maps); in `trinary` mode it is unknown.
fn classify(avg: f64, h: &Header) -> (Cell, u8) {
    let occ = match h.mode {
        Mode::Raw => {
            if avg > 100.0 {
                return (Cell::Unknown, 0);
            }
            avg / 100.0
        }
        Mode::Trinary | Mode::Scale => {
            let v = if h.negate { 255.0 - avg } else { avg };
            (255.0 - v) / 255.0
        }
    };
    if occ > h.occupied_thresh {
        (Cell::Occupied, 0)
    } else if occ < h.free_thresh {
        (Cell::Free, 0)
    } else if h.mode == Mode::Trinary {
        (Cell::Unknown, 0)
    } else {
        let span = (h.occupied_thresh - h.free_thresh).max(f64::MIN_POSITIVE);
        let cost = 1.0 + 251.0 * ((occ - h.free_thresh) / span).clamp(0.0, 1.0);
        (Cell::Free, cost.round() as u8)
    }
}

impl OccupancyMap {
    /// Reads a `map_server` YAML file and the image it names (relative to the YAML's folder).
    pub fn load(yaml: impl AsRef<Path>) -> Result<OccupancyMap, MapError> {
        let yaml = yaml.as_ref();
        let file = yaml.display().to_string();
        let text = std::fs::read_to_string(yaml).map_err(|source| MapError::Io {
            file: file.clone(),
            source,
        })?;
        let dir = yaml.parent().unwrap_or(Path::new("."));
        let header = parse_header(&text, &file, dir)?;
        let image_file = header.image.display().to_string();
        let bytes = std::fs::read(&header.image).map_err(|source| MapError::Io {
            file: format!("{image_file} (field `image` of {file})"),
            source,
        })?;
        let mut map = OccupancyMap::decoded(&header, &bytes, image_file)?;
        map.source = file;
        Ok(map)
    }

    /// A map from the text of a `map_server` YAML document and the bytes of its image (its
    /// `image` field must name a file, which is not read: the image is `image`); `name`
    /// stands for the files in messages. What [`OccupancyMap::load`] does once the files are
    /// read, for maps that come from elsewhere than files (and for fuzzing).
    pub fn from_bytes(yaml: &str, image: &[u8], name: &str) -> Result<OccupancyMap, MapError> {
        let header = parse_header(yaml, name, Path::new(""))?;
        let mut map = OccupancyMap::decoded(&header, image, name.to_string())?;
        map.source = name.to_string();
        Ok(map)
    }

    /// Decodes the image `bytes` (PGM or PNG, named `image_file` in messages) and classifies
    /// its pixels by `header`.
    pub(super) fn decoded(
        header: &Header,
        bytes: &[u8],
        image_file: String,
    ) -> Result<OccupancyMap, MapError> {
        let img = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| MapError::Image {
                file: image_file.clone(),
                message: e.to_string(),
            })?
            .decode()
            .map_err(|e| MapError::Image {
                file: image_file.clone(),
                message: e.to_string(),
            })?;
        let (width, height) = (img.width() as usize, img.height() as usize);
        if width == 0 || height == 0 {
            return Err(MapError::EmptyMap { file: image_file });
        }
        // The rule depends on a pixel only through the sum of its channels (0..=765): one
        // table, then a look-up per pixel; a grey image (most maps) is read as it is.
        let rule: Vec<(Cell, u8)> = (0..=765u16)
            .map(|sum| classify(f64::from(sum) / 3.0, header))
            .collect();
        let sums: Vec<u16> = match &img {
            image::DynamicImage::ImageLuma8(grey) => {
                grey.as_raw().iter().map(|&v| 3 * u16::from(v)).collect()
            }
            _ => img
                .to_rgb8()
                .as_raw()
                .chunks_exact(3)
                .map(|p| u16::from(p[0]) + u16::from(p[1]) + u16::from(p[2]))
                .collect(),
        };
        let mut cells = Vec::with_capacity(width * height);
        let mut costs = Vec::with_capacity(width * height);
        // Image rows run from the top; the map's row 0 is the bottom one.
        for row in sums.chunks_exact(width).rev() {
            for &sum in row {
                let (cell, cost) = rule[usize::from(sum)];
                cells.push(cell);
                costs.push(cost);
            }
        }
        let map = OccupancyMap::from_cells(width, height, header.resolution, header.origin, cells)?;
        if costs.iter().any(|&c| c > 0) {
            map.with_costs(costs)
        } else {
            Ok(map)
        }
    }

    /// A map from cells listed row by row, row 0 at the bottom.
    pub fn from_cells(
        width: usize,
        height: usize,
        resolution: f64,
        origin: [f64; 3],
        cells: Vec<Cell>,
    ) -> Result<OccupancyMap, MapError> {
        if width.saturating_mul(height) > MAX_MAP_CELLS {
            return Err(MapError::BadGrid(format!(
                "a {width} × {height} grid has more than {MAX_MAP_CELLS} cells, the most a map may have"
            )));
        }
        if width == 0 || height == 0 || cells.len() != width * height {
            return Err(MapError::BadGrid(format!(
                "a {width} × {height} grid needs {} cells, got {}",
                width * height,
                cells.len()
            )));
        }
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(MapError::BadGrid(format!(
                "resolution must be positive, got {resolution}"
            )));
        }
        if !origin.iter().all(|v| v.is_finite()) {
            return Err(MapError::BadGrid(format!(
                "origin must be finite, got {origin:?}"
            )));
        }
        let bits = |kind: Cell| BitGrid::from_slice(width, height, &cells, |c| c == kind);
        Ok(OccupancyMap {
            width,
            height,
            resolution,
            origin,
            occupied: bits(Cell::Occupied),
            unknown: bits(Cell::Unknown),
            cells,
            costs: None,
            source: "map".into(),
            offset: [0, 0],
            extent: [width, height],
        })
    }

    /// The map with graded costs for its free cells, row by row as the cells (0 none, 1 …
    /// 252 the costliest; values above 252 are refused, and costs of blocked cells are
    /// ignored). With [`MapOptions::cost_weight`] w > 0 they shape the field: a cell of cost
    /// c conducts 1 / (1 + w·0.016·c) of a free cell's flow and absorbs
    /// w·[`cost_absorption`]`(c)` / (0.05 m)².
    pub fn with_costs(mut self, costs: Vec<u8>) -> Result<OccupancyMap, MapError> {
        if costs.len() != self.cells.len() {
            return Err(MapError::BadGrid(format!(
                "{} costs for a {} × {} grid",
                costs.len(),
                self.width,
                self.height
            )));
        }
        if let Some(i) = costs.iter().position(|&c| c > MAX_GRADED_COST) {
            return Err(MapError::BadGrid(format!(
                "cost {} of cell (column {}, row {}) is above {MAX_GRADED_COST}, the costliest free cell",
                costs[i],
                i % self.width,
                i / self.width
            )));
        }
        self.costs = Some(Arc::new(costs));
        Ok(self)
    }

    /// The graded cost of cell `(column, row)` (0 without costs).
    pub fn cost(&self, column: usize, row: usize) -> u8 {
        self.costs
            .as_ref()
            .and_then(|c| c.get(row * self.width + column).copied())
            .unwrap_or(0)
    }

    /// The graded cost of the cell under a point (0 off the map and on cells without cost).
    fn cost_under(&self) -> impl Fn(Point) -> u8 + Send + Sync + 'static {
        let costs = self.costs.clone().unwrap_or_default();
        let frame = self.frame();
        let (w, h) = (self.width, self.height);
        move |p: Point| {
            let g = frame.world_to_grid([p.x, p.y]);
            let (i, j) = (g[0].floor(), g[1].floor());
            if i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h {
                costs.get(j as usize * w + i as usize).copied().unwrap_or(0)
            } else {
                0
            }
        }
    }

    /// The conductivity of the cell under a point for `weight`: 1 / (1 + weight·0.016·c)
    /// for a cell of cost c (1 off the map and on cells without cost).
    pub(super) fn conductivity(&self, weight: f64) -> crate::planner::Conductivity {
        let cost = self.cost_under();
        Arc::new(move |p: Point| 1.0 / (1.0 + weight * COST_RESISTANCE * f64::from(cost(p))))
    }

    /// The absorption of the cell under a point for `weight`: σ = weight·0.016·c·(c/252)³ / ℓ²
    /// for a cell of cost c ([`cost_absorption`], ℓ = [`COST_ABSORPTION_LENGTH`]; 0 off the
    /// map and on cells without cost).
    pub(super) fn absorption(&self, weight: f64) -> crate::planner::Absorption {
        let cost = self.cost_under();
        let per_area = 1.0 / (COST_ABSORPTION_LENGTH * COST_ABSORPTION_LENGTH);
        Arc::new(move |p: Point| weight * cost_absorption(cost(p)) * per_area)
    }

    /// The graded costs as rectangles for a picture: runs of equal cost along each row, in
    /// world coordinates, each with its cost / 252 ([`crate::planner::SvgOptions::shaded`]).
    pub fn cost_shading(&self) -> Vec<(Vec<[f64; 2]>, f64)> {
        let mut out = Vec::new();
        let Some(costs) = &self.costs else {
            return out;
        };
        for row in 0..self.height {
            let mut column = 0;
            while column < self.width {
                let c = costs[row * self.width + column];
                let mut end = column + 1;
                while end < self.width && costs[row * self.width + end] == c {
                    end += 1;
                }
                if c > 0 {
                    let (x0, x1, y0, y1) =
                        (column as f64, end as f64, row as f64, row as f64 + 1.0);
                    let ring = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
                        .map(|g| self.grid_to_world(g))
                        .to_vec();
                    out.push((ring, f64::from(c) / f64::from(MAX_GRADED_COST)));
                }
                column = end;
            }
        }
        out
    }

    /// Whether some free cell has a graded cost.
    pub(super) fn has_graded_costs(&self, unknown: UnknownCells) -> bool {
        self.costs.as_ref().is_some_and(|costs| {
            costs
                .iter()
                .enumerate()
                .any(|(i, &c)| c > 0 && !self.is_blocked(i % self.width, i / self.width, unknown))
        })
    }
}
