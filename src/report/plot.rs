//! Line charts (SVG and PNG) for the reproduction report, drawn with plotters.
//!
//! Steps of one chart: pick the data ranges (`Chart::ranges`), choose the tick values
//! ([`log_ticks`] on a log axis, [`linear_label`] formats a linear one), draw grid, axes and
//! curves, then the legend in its own strip under the plot so it never covers a curve.
//! PNG text goes through `GlyphText`, which lays glyphs out itself (see there why).

use ab_glyph::{Font, FontRef, ScaleFont, point};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{
    KeyPointHint, KeyPointWeight, NoDefaultFormatting, ValueFormatter,
};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Once;

use super::ReportError;

/// A plotting error for the chart file `path`.
fn plot_err(path: &Path, message: String) -> ReportError {
    ReportError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// One named polyline of (x, y) points.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points in data units; non-finite or (on a log axis) non-positive values are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw as a dashed horizontal reference instead of a solid line.
    pub reference: bool,
}

/// A chart: title, axis labels, series and whether the y axis is logarithmic.
#[derive(Debug, Clone)]
pub struct Chart {
    /// Title drawn above the plot.
    pub title: String,
    /// x axis label.
    pub x_label: String,
    /// y axis label.
    pub y_label: String,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The curves.
    pub series: Vec<Series>,
}

const FONT: &str = "sans-serif";
/// egui's bundled Ubuntu Light font: no system font lookup, so PNGs render the same everywhere.
const FONT_BYTES: &[u8] = epaint_default_fonts::UBUNTU_LIGHT;
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];
/// Image size in pixels.
const SIZE: (u32, u32) = (1000, 600);
/// Height of the legend strip under the plot, pixels.
const LEGEND_HEIGHT: u32 = 40;

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES);
    });
}

/// Tick values to label on a log axis over `[lo, hi]` (both > 0): every power of ten inside
/// the range, plus 2× and 5× when the range spans at most three decades, plus every integer
/// mantissa when it spans less than one, so that at least two ticks are labelled whenever the
/// range allows. Each value is an integer mantissa times a power of ten, so [`log_label`]
/// gives distinct labels.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let decades = (hi / lo).log10();
    let mantissas: &[f64] = if decades < 1.0 {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    } else if decades <= 3.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    mantissa_ticks(lo, hi, mantissas)
}

/// Every `m × 10^e` in `[lo, hi]` for the given mantissas, ascending.
fn mantissa_ticks(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    let first = lo.log10().floor() as i32;
    let last = hi.log10().ceil() as i32;
    for e in first..=last {
        for &m in mantissas {
            let v = m * 10f64.powi(e);
            // Relative slack so a tick at exactly the range end is kept despite rounding.
            if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                out.push(v);
            }
        }
    }
    out
}

/// A log-axis tick label for a tick of [`log_ticks`] (an integer mantissa times a power of
/// ten): a plain number from 0.001 to below 10,000 (`0.002`, `1`, `20`, `5000`), engineering
/// notation outside it, the exponent a multiple of three as in the reports' tables (`200e-6`,
/// `10e3`, `1e6`); never a lone `2e1`.
pub fn log_label(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return format!("{v}");
    }
    let exponent = v.log10().round_ties_even() as i32;
    // The tick's own power of ten: its mantissa is 1..9.
    let power = if 10f64.powi(exponent) > v * (1.0 + 1e-9) {
        exponent - 1
    } else {
        exponent
    };
    if (-3..4).contains(&power) {
        let decimals = (-power).max(0) as usize;
        return format!("{v:.decimals$}");
    }
    let three = power.div_euclid(3) * 3;
    let mantissa = (v / 10f64.powi(three)).round();
    format!("{mantissa}e{three}")
}

/// A linear-axis tick label in plain numbers with as many decimals as a tick step of `span / 10`
/// needs (`0.05`, `-0.10`, `1500`).
pub fn linear_label(v: f64, span: f64) -> String {
    let step = (span / 10.0).abs().max(f64::MIN_POSITIVE);
    let decimals = (-step.log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{v:.decimals$}");
    // "-0.00" reads as a different value from "0.00".
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// A logarithmic y axis whose labelled ticks are [`log_ticks`] and whose light grid lines fall
/// on every integer mantissa (plotters' own log axis labels near-duplicate values such as
/// 9.5e-4 and 1.0e-3 as `1.0e-3` twice and skips decades).
#[derive(Debug, Clone)]
struct LogAxis {
    lo: f64,
    hi: f64,
}

impl Ranged for LogAxis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let (a, b) = (self.lo.log10(), self.hi.log10());
        let t = (value.max(f64::MIN_POSITIVE).log10() - a) / (b - a);
        limit.0 + ((limit.1 - limit.0) as f64 * t).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        match hint.weight() {
            KeyPointWeight::Bold => log_ticks(self.lo, self.hi),
            KeyPointWeight::Any => mantissa_ticks(
                self.lo,
                self.hi,
                &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
            ),
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for LogAxis {
    fn format(value: &f64) -> String {
        log_label(*value)
    }
}

impl Chart {
    /// Write `<stem>.svg` and `<stem>.png` (1000×600) and return both paths. Both are drawn in
    /// memory and written atomically (temporary file + rename).
    pub fn write(&self, stem: &Path) -> Result<[PathBuf; 2], ReportError> {
        register_font();
        let svg = stem.with_extension("svg");
        let png = stem.with_extension("png");
        let mut svg_text = String::new();
        {
            let root = SVGBackend::with_string(&mut svg_text, SIZE).into_drawing_area();
            self.draw(&root).map_err(|m| plot_err(&svg, m))?;
            root.present().map_err(|e| plot_err(&svg, e.to_string()))?;
        }
        mesh::io::write_atomic(&svg, svg_text.as_bytes())?;
        let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let font = FontRef::try_from_slice(FONT_BYTES)
                .map_err(|e| plot_err(&png, format!("font: {e}")))?;
            let backend = GlyphText {
                inner: BitMapBackend::with_buffer(&mut rgb, SIZE),
                font,
            };
            let root = backend.into_drawing_area();
            self.draw(&root).map_err(|m| plot_err(&png, m))?;
            root.present().map_err(|e| plot_err(&png, e.to_string()))?;
        }
        let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, rgb)
            .ok_or_else(|| plot_err(&png, "bitmap size mismatch".into()))?;
        let mut encoded = std::io::Cursor::new(Vec::new());
        image
            .write_to(&mut encoded, image::ImageFormat::Png)
            .map_err(|e| plot_err(&png, e.to_string()))?;
        mesh::io::write_atomic(&png, encoded.get_ref())?;
        Ok([svg, png])
    }

    fn usable(&self, y: f64) -> bool {
        y.is_finite() && (!self.log_y || y > 0.0)
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let mut x = (f64::INFINITY, f64::NEG_INFINITY);
        let mut y = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &self.series {
            for &(px, py) in &s.points {
                if px.is_finite() && self.usable(py) {
                    x = (x.0.min(px), x.1.max(px));
                    y = (y.0.min(py), y.1.max(py));
                }
            }
        }
        if !x.0.is_finite() {
            x = (0.0, 1.0);
            y = if self.log_y { (1e-6, 1.0) } else { (0.0, 1.0) };
        }
        if x.1 <= x.0 {
            x.1 = x.0 + 1.0;
        }
        if self.log_y {
            y = (y.0 / 1.5, y.1 * 1.5);
        } else {
            let pad = ((y.1 - y.0) * 0.08).max(y.1.abs() * 1e-3).max(1e-12);
            y = (y.0 - pad, y.1 + pad);
        }
        (x, y)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
        root.fill(&WHITE).map_err(err)?;
        let (plot_area, legend_area) = root.split_vertically(SIZE.1 - LEGEND_HEIGHT);
        let ((x0, x1), (y0, y1)) = self.ranges();
        let mut builder = ChartBuilder::on(&plot_area);
        builder
            .caption(&self.title, (FONT, 26))
            .margin(16)
            .margin_bottom(4)
            .x_label_area_size(44)
            .y_label_area_size(90);
        if self.log_y {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, LogAxis { lo: y0, hi: y1 })
                .map_err(err)?;
            self.decorate(&mut chart, &|v| log_label(*v)).map_err(err)?;
        } else {
            let mut chart = builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?;
            let span = y1 - y0;
            self.decorate(&mut chart, &|v| linear_label(*v, span))
                .map_err(err)?;
        }
        self.draw_legend(&legend_area).map_err(err)
    }

    /// Axes, grid, labels (y values formatted by `y_format`) and the series.
    fn decorate<'a, DB, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
        y_format: &dyn Fn(&f64) -> String,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
    where
        DB: DrawingBackend + 'a,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(y_format)
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()?;
        self.draw_series(chart)
    }

    /// One row of legend entries (line sample + label), centred in `area` under the plot.
    fn draw_legend<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        const SAMPLE: i32 = 28;
        const GAP: i32 = 8;
        const SPACING: i32 = 32;
        let text = TextStyle::from((FONT, 16).into_font()).pos(
            plotters::style::text_anchor::Pos::new(HPos::Left, VPos::Center),
        );
        let widths: Vec<i32> = self
            .series
            .iter()
            .map(|s| {
                area.estimate_text_size(&s.label, &text)
                    .map(|(w, _)| w as i32)
            })
            .collect::<Result<_, _>>()?;
        let total: i32 = widths.iter().map(|w| SAMPLE + GAP + w).sum::<i32>()
            + SPACING * (widths.len() as i32 - 1).max(0);
        let (w, h) = area.dim_in_pixel();
        let mut x = ((w as i32 - total) / 2).max(4);
        let y = h as i32 / 2;
        for (i, (s, width)) in self.series.iter().zip(widths).enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let style = ShapeStyle::from(color).stroke_width(2);
            if s.reference {
                for k in 0..3 {
                    let a = x + k * 10;
                    area.draw(&PathElement::new(vec![(a, y), (a + 6, y)], style))?;
                }
            } else {
                area.draw(&PathElement::new(vec![(x, y), (x + SAMPLE, y)], style))?;
                area.draw(&Circle::new((x + SAMPLE / 2, y), 3, color.filled()))?;
            }
            area.draw(&Text::new(
                s.label.clone(),
                (x + SAMPLE + GAP, y),
                text.clone(),
            ))?;
            x += SAMPLE + GAP + width + SPACING;
        }
        Ok(())
    }

    fn draw_series<'a, DB, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
    where
        DB: DrawingBackend + 'a,
        Y: Ranged<ValueType = f64>,
    {
        for (i, s) in self.series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| x.is_finite() && self.usable(y))
                .collect();
            let style = ShapeStyle::from(color).stroke_width(2);
            if s.reference {
                chart.draw_series(DashedLineSeries::new(pts, 8, 5, style))?;
            } else {
                chart.draw_series(LineSeries::new(pts.clone(), style))?;
                chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
            }
        }
        Ok(())
    }
}

/// A bitmap backend that lays out text itself. plotters 0.3.7's ab_glyph path places each
/// glyph's bitmap at the pen position without its left side bearing (and truncates the pen
/// to whole pixels per glyph), which renders "GNG3D" as "GN G3D"; here every glyph is
/// positioned at its sub-pixel pen position, so its outline bounds carry the bearing.
/// Everything else is delegated to the wrapped backend.
struct GlyphText<'f, B> {
    inner: B,
    font: FontRef<'f>,
}

impl<B: DrawingBackend> DrawingBackend for GlyphText<'_, B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }
    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    /// Same anchoring and rotation as plotters' default (its layout box), but glyph placement
    /// from ab_glyph's own positioned outlines.
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let font = self.font.as_scaled(style.size() as f32);
        // Baseline inside the layout box in the font's own ascent : descent proportion.
        let baseline = height as f32 * font.ascent() / (font.ascent() - font.descent());
        let trans = style.transform();
        let (w, h) = self.get_size();
        let mut pen = 0.0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                pen += font.kern(p, id);
            }
            prev = Some(id);
            let glyph = id.with_scale_and_position(font.scale(), point(pen, baseline));
            pen += font.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            let mut pixels = Vec::new();
            outline.draw(|x, y, coverage| pixels.push((x, y, coverage)));
            for (x, y, coverage) in pixels {
                if coverage <= 0.0 {
                    continue;
                }
                let lx = bounds.min.x as i32 + x as i32;
                let ly = bounds.min.y as i32 + y as i32;
                let (tx, ty) = trans.transform(lx + dx, ly + dy);
                let (px, py) = (pos.0 + tx, pos.1 + ty);
                if px >= 0 && px < w as i32 && py >= 0 && py < h as i32 {
                    let pixel = BackendColor {
                        alpha: color.alpha * f64::from(coverage.min(1.0)),
                        rgb: color.rgb,
                    };
                    self.inner.draw_pixel((px, py), pixel)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_nonempty_svg_and_png() {
        let dir = tempfile::tempdir().unwrap();
        let chart = Chart {
            title: "E_avg vs iteration".into(),
            x_label: "iteration".into(),
            y_label: "E_avg".into(),
            log_y: true,
            series: vec![
                Series {
                    label: "GNG3D".into(),
                    points: (1..10).map(|i| (i as f64, 1.0 / i as f64)).collect(),
                    reference: false,
                },
                Series {
                    label: "QEM".into(),
                    points: vec![(1.0, 0.2), (9.0, 0.2)],
                    reference: true,
                },
            ],
        };
        let [svg, png] = chart.write(&dir.path().join("plot")).unwrap();
        let svg_text = std::fs::read_to_string(&svg).unwrap();
        assert!(svg_text.contains("GNG3D") && svg_text.contains("<polyline"));
        let png_bytes = std::fs::read(png).unwrap();
        assert_eq!(&png_bytes[1..4], b"PNG");
        assert!(png_bytes.len() > 5_000);
    }

    /// Ranges seen in real reports (gargoyle-10k E_avg, E_max, Hausdorff) and edge cases.
    const RANGES: [(f64, f64); 7] = [
        (1.7e-5, 1.0e-3),
        (2.6e-5, 9.6e-4),
        (3.0e-4, 8.0e-4),
        (1.1e-3, 4.0e-2),
        (1e-9, 1.0),
        (0.5, 20.0),
        (1e-4, 1e-3),
    ];

    #[test]
    fn log_ticks_have_distinct_labels_and_cover_every_decade() {
        for (lo, hi) in RANGES {
            let ticks = log_ticks(lo, hi);
            let labels: Vec<String> = ticks.iter().map(|&v| log_label(v)).collect();
            let mut unique = labels.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "{lo}..{hi}: {labels:?}");
            assert!(ticks.len() >= 2, "{lo}..{hi}: {labels:?}");
            assert!(ticks.iter().all(|&t| t >= lo * 0.999 && t <= hi * 1.001));
            assert!(ticks.windows(2).all(|w| w[0] < w[1]));
            // Every power of ten inside the range, computed independently, is labelled.
            let mut e = -30;
            while e <= 30 {
                let p = 10f64.powi(e);
                if p >= lo && p <= hi {
                    assert!(
                        labels
                            .iter()
                            .any(|l| (l.parse::<f64>().unwrap() - p).abs() <= 1e-9 * p),
                        "{lo}..{hi}: 1e{e} not in {labels:?}"
                    );
                }
                e += 1;
            }
        }
    }

    #[test]
    fn log_labels_round_trip_to_their_tick() {
        for (lo, hi) in RANGES {
            for t in log_ticks(lo, hi) {
                let parsed: f64 = log_label(t).parse().unwrap();
                assert!((parsed - t).abs() <= 1e-9 * t, "{t} -> {}", log_label(t));
            }
        }
        let cases = [
            (1e-4, "100e-6"),
            (2e-4, "200e-6"),
            (1e-3, "0.001"),
            (0.05, "0.05"),
            (2.0, "2"),
            (20.0, "20"),
            (5000.0, "5000"),
            (1e4, "10e3"),
            (3e5, "300e3"),
            (1e6, "1e6"),
            (1e-9, "1e-9"),
        ];
        for (v, want) in cases {
            assert_eq!(log_label(v), want, "{v}");
        }
        assert!(log_ticks(0.0, 1.0).is_empty());
    }

    #[test]
    fn linear_labels_are_plain_and_distinct_per_step() {
        let span = 0.25;
        let labels: Vec<String> = (0..=10)
            .map(|i| linear_label(-0.05 + i as f64 * span / 10.0, span))
            .collect();
        assert!(labels.iter().all(|l| !l.contains('e')), "{labels:?}");
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(unique.len(), labels.len(), "{labels:?}");
        assert_eq!(linear_label(-0.0001, 0.25), "0.00");
        assert_eq!(linear_label(1500.0, 3000.0), "1500");
    }
}
