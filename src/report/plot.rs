//! Line charts (SVG and PNG) for the reproduction report, drawn with plotters.

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
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
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // egui's bundled Ubuntu font: no system font lookup, so PNGs render the same everywhere.
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

impl Chart {
    /// Write `<stem>.svg` and `<stem>.png` (1000×600) and return both paths. Both are drawn in
    /// memory and written atomically (temporary file + rename).
    pub fn write(&self, stem: &Path) -> Result<[PathBuf; 2], ReportError> {
        const SIZE: (u32, u32) = (1000, 600);
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
            let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
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
        let ((x0, x1), (y0, y1)) = self.ranges();
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.title, (FONT, 26))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(90);
        if self.log_y {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(err)?;
            self.decorate(&mut chart, &|v| format!("{v:.1e}"))
                .map_err(err)?;
        } else {
            let mut chart = builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?;
            self.decorate(&mut chart, &|v| format!("{v:.3e}"))
                .map_err(err)?;
        }
        Ok(())
    }

    /// Axes, grid, labels (y values formatted by `y_format`), the series and the legend.
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
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(y_format)
            .draw()?;
        self.draw_series(chart)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 15))
            .draw()
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
                chart
                    .draw_series(DashedLineSeries::new(pts, 8, 5, style))?
                    .label(&s.label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))?
                    .label(&s.label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
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
}
