//! The plots' axes: log10 and signal-count grid marks whose labels never crowd nor vanish, the
//! tick and hover number formats, and the base plots every figure starts from.

use egui_plot::{GridInput, GridMark, Plot};
pub(super) fn log10(v: f64) -> f64 {
    v.max(1e-30).log10()
}

/// Least distance between two labelled y ticks, points (a line of tick text is ~16 points).
const MIN_Y_LABEL_GAP: f32 = 26.0;
/// Least distance between two labelled x ticks, points ("1.25M" is ~40 points wide).
const MIN_X_LABEL_GAP: f32 = 64.0;

/// Points per axis unit, from what egui_plot hands a grid spacer: `base_step_size` is the
/// axis units per the plot's smallest grid spacing ([`GRID_MIN_SPACING`] points).
fn points_per_unit(input: &GridInput) -> f32 {
    if input.base_step_size > 0.0 && input.base_step_size.is_finite() {
        (f64::from(GRID_MIN_SPACING) / input.base_step_size) as f32
    } else {
        0.0
    }
}

/// Smallest spacing of the plots' grid lines, points.
const GRID_MIN_SPACING: f32 = 24.0;

/// A labelled tick. egui_plot hides or fades a tick's label when `step_size` spans fewer than
/// 20-30 points (y) or 60-80 points (x), which made the labels vanish on plots with many
/// decades or little height; the spacers here choose their labelled ticks far enough apart
/// themselves, so every labelled tick carries the whole axis span as its step size (full
/// strength), and [`is_labelled`] tells the formatters which ones they are.
fn labelled(value: f64, span: f64) -> GridMark {
    GridMark {
        value,
        step_size: span,
    }
}

/// An unlabelled grid line (a tenth of the span: a faint line).
fn unlabelled(value: f64, span: f64) -> GridMark {
    GridMark {
        value,
        step_size: 0.1 * span,
    }
}

/// Whether a mark of an axis showing `range` is one of the labelled ticks.
fn is_labelled(mark: &GridMark, range: &std::ops::RangeInclusive<f64>) -> bool {
    mark.step_size >= 0.5 * (range.end() - range.start()).abs()
}

/// Two labelled ticks near the ends of the range (a twentieth of it inside: where the data's
/// extremes sit with egui_plot's margins), for a range where no round values fit.
fn end_marks(lo: f64, hi: f64) -> Vec<GridMark> {
    let span = hi - lo;
    vec![
        labelled(lo + span / 22.0, span),
        labelled(hi - span / 22.0, span),
    ]
}

/// Grid marks of a log10-transformed axis whose labels never crowd and never vanish: decades
/// (every 1, 2, 3, 5 or 10 decades, as the plot's height allows); within less than two decades
/// the 1-2-5 values when they are far enough apart; otherwise two ticks near the ends. Every
/// axis gets at least two labelled ticks (issue 37: a plot with one tick or none).
fn log_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(lo.is_finite() && hi.is_finite()) || span <= 0.0 {
        return Vec::new();
    }
    let ppu = points_per_unit(&input).max(1e-6);
    let inside = |v: f64| v >= lo && v <= hi;
    let decades: Vec<i64> = ((lo.ceil() as i64)..=(hi.floor() as i64)).collect();
    if decades.len() > 400 {
        return end_marks(lo, hi);
    }
    let mut marks = Vec::new();
    if decades.len() >= 2 {
        let stride = [1, 2, 3, 5, 10, 20, 50, 100]
            .into_iter()
            .find(|&s| s as f32 * ppu >= MIN_Y_LABEL_GAP)
            .unwrap_or(100);
        let chosen: Vec<i64> = decades
            .iter()
            .copied()
            .filter(|d| d.rem_euclid(stride) == 0)
            .collect();
        if chosen.len() >= 2 {
            for d in decades {
                marks.push(if d.rem_euclid(stride) == 0 {
                    labelled(d as f64, span)
                } else {
                    unlabelled(d as f64, span)
                });
            }
            return marks;
        }
    }
    // Less than two decades (or too little height for two of them): 1-2-5 values, the closest
    // two of which (5 and 10) are 0.3 decades apart.
    let nice: Vec<f64> = ((lo.floor() as i64)..=(hi.ceil() as i64))
        .flat_map(|k| [1f64, 2.0, 5.0].map(|m| k as f64 + m.log10()))
        .filter(|&v| inside(v))
        .collect();
    if nice.len() >= 2 && 0.3 * ppu >= MIN_Y_LABEL_GAP {
        return nice.into_iter().map(|v| labelled(v, span)).collect();
    }
    let mut marks = end_marks(lo, hi);
    marks.extend(nice.into_iter().map(|v| unlabelled(v, span)));
    marks
}

/// Linear x marks (signals): round values (1, 2 or 5 × 10^k apart) at least
/// [`MIN_X_LABEL_GAP`] points apart from 0 up to `end` (the run's budget), and `end` itself
/// labelled when the last round value is short of it, so the axis always shows where it starts
/// and ends (issue 13: labels never repeat one value; issue 37: end values always shown).
fn count_marks(input: GridInput, end: f64) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let ppu = f64::from(points_per_unit(&input)).max(1e-12);
    let raw = (f64::from(MIN_X_LABEL_GAP) / ppu).max(span / 8.0);
    let decade = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * decade)
        .max(1.0);
    let first = (lo.max(0.0) / step).ceil() as i64;
    let last_value = if end > 0.0 && end <= hi { end } else { hi };
    let last = (last_value / step).floor() as i64;
    let mut values: Vec<f64> = (first..=last).map(|i| i as f64 * step).collect();
    if end > 0.0 && end <= hi {
        let gap = f64::from(MIN_X_LABEL_GAP) / ppu;
        // The budget's own tick replaces a round value too close to it.
        while values.last().is_some_and(|&v| end - v < gap && v != 0.0) {
            values.pop();
        }
        if values.last().is_none_or(|&v| end - v >= gap) {
            values.push(end);
        }
    }
    values.into_iter().map(|v| labelled(v, span)).collect()
}

/// A number for a tick or a table cell, with `digits` significant digits: plain between 0.001
/// and 10,000 ("0.0073", "7.3", "730"), engineering notation outside (exponent a multiple of
/// 3: "73e-6", "1.5e6"); never "7.3e0" (issue 37).
pub fn format_value(v: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    let exponent = a.log10().floor() as i32;
    if (-3..4).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        let s = format!("{v:.decimals$}");
        // Rounding up can add a digit (9.96 → "10.0"): drop the extra decimal.
        return if decimals > 0 && s.contains('.') {
            let t = s.trim_end_matches('0').trim_end_matches('.');
            t.to_string()
        } else {
            s
        };
    }
    let mut eng = exponent.div_euclid(3) * 3;
    let mut mantissa = v / 10f64.powi(eng);
    let mut decimals =
        (digits as i32 - 1 - (mantissa.abs().log10().floor() as i32)).max(0) as usize;
    let mut text = format!("{mantissa:.decimals$}");
    if text
        .trim_start_matches('-')
        .parse::<f64>()
        .is_ok_and(|m| m >= 1000.0)
    {
        eng += 3;
        mantissa = v / 10f64.powi(eng);
        decimals = digits.saturating_sub(1);
        text = format!("{mantissa:.decimals$}");
    }
    if text.contains('.') {
        text = text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{text}e{eng}")
}

/// A log-axis tick: `10^mark`, two significant digits (a round 1-2-5 value prints with one).
fn format_log_tick(mark: GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    if !is_labelled(&mark, range) {
        return String::new();
    }
    format_value(10f64.powf(mark.value), 2)
}

/// Compact signal counts for the x axis: 0, 500, 12k, 1.5M.
pub fn format_count(v: f64) -> String {
    let a = v.abs();
    if a >= 1e6 {
        format!("{}M", trim_float(v / 1e6))
    } else if a >= 1e3 {
        format!("{}k", trim_float(v / 1e3))
    } else {
        format!("{v:.0}")
    }
}

/// `v` with at most two decimals and no trailing zeros.
fn trim_float(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The series name (empty away from data) and plot position under the pointer.
pub(super) fn hovered<'a>(
    pos: &'a egui_plot::HoverPosition<'_>,
) -> (&'a str, egui_plot::PlotPoint) {
    match pos {
        egui_plot::HoverPosition::NearDataPoint {
            plot_name,
            position,
            ..
        } => (plot_name, *position),
        egui_plot::HoverPosition::Elsewhere { position } => ("", *position),
    }
}

/// Base plot: no background, sparse grid, x from 0 to the signal budget with compact labels
/// at both ends.
fn base_plot(id: &str, height: f32, x_max: f64) -> Plot<'static> {
    let end = x_max.max(1.0);
    Plot::new(id)
        .height(height)
        // The panel colour shows through: no second fill of the plot area.
        .show_background(false)
        // Grid lines at least 24 px apart (egui_plot's default, 8 px, draws ~3× as many faint
        // lines, each of which a CPU rasterizer pays for).
        .grid_spacing(egui::Rangef::new(GRID_MIN_SPACING, 300.0))
        .include_x(0.0)
        .include_x(end)
        .x_grid_spacer(move |input| count_marks(input, end))
        .x_axis_formatter(|mark, range| {
            if is_labelled(&mark, range) {
                format_count(mark.value)
            } else {
                String::new()
            }
        })
        .x_axis_label("signals")
        .allow_scroll(false)
}

/// The log10 y range a plot of `values` (already log10) shows at least: the values, and at
/// least [`MIN_LOG_SPAN`] decades around their middle, so a single point or a flat line gets
/// a sensible axis with labelled ticks on both sides (issue 37).
pub fn log_y_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return None;
    }
    let middle = 0.5 * (lo + hi);
    let half = (0.5 * MIN_LOG_SPAN).max(0.5 * (hi - lo));
    Some((lo.min(middle - half), hi.max(middle + half)))
}

/// Least decades a log plot spans (a lone value gets a third of a decade either side).
pub const MIN_LOG_SPAN: f64 = 0.7;

/// Base plot with a log10 y axis: its y range holds `values` (log10, see [`log_y_range`]).
pub(super) fn log_plot(
    id: &str,
    height: f32,
    x_max: f64,
    values: impl IntoIterator<Item = f64>,
) -> Plot<'static> {
    let mut plot = base_plot(id, height, x_max)
        .y_grid_spacer(log_marks)
        .y_axis_formatter(format_log_tick);
    let (lo, hi) = log_y_range(values).unwrap_or((-3.0, 0.0));
    plot = plot.include_y(lo).include_y(hi);
    plot
}

/// Hover text of a log plot: series, signals, value with its unit.
pub(super) fn log_hover(
    unit: &'static str,
) -> impl Fn(&egui_plot::HoverPosition<'_>) -> Option<String> {
    move |pos| {
        let (name, p) = hovered(pos);
        Some(format!(
            "{name}\n{} signals\n{} {unit}",
            format_count(p.x),
            format_value(10f64.powf(p.y), 3)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The labelled ticks of a log axis from `lo` to `hi` (values, not logs) drawn `points`
    /// high, as egui_plot asks for them, with their labels.
    fn log_labels(lo: f64, hi: f64, points: f64) -> Vec<String> {
        let (lo, hi) = (lo.log10(), hi.log10());
        let range = lo..=hi;
        log_marks(GridInput {
            bounds: (lo, hi),
            base_step_size: (hi - lo) / points * f64::from(GRID_MIN_SPACING),
        })
        .into_iter()
        .map(|m| format_log_tick(m, &range))
        .filter(|l| !l.is_empty())
        .collect()
    }

    #[test]
    fn numbers_read_plainly_or_in_engineering_notation() {
        for (v, digits, want) in [
            (7.3, 2, "7.3"),
            (7.0, 2, "7"),
            (0.0073, 2, "0.0073"),
            (730.0, 2, "730"),
            (7.3e-5, 2, "73e-6"),
            (1e-4, 1, "100e-6"),
            (1.5e6, 2, "1.5e6"),
            (12345.0, 3, "12.3e3"),
            (-0.5, 3, "-0.5"),
            (9.996, 3, "10"),
            (999_999.0, 2, "1e6"),
            (0.0, 3, "0"),
        ] {
            assert_eq!(format_value(v, digits), want, "{v} with {digits} digits");
        }
        assert_eq!(format_count(20_000.0), "20k");
        assert_eq!(format_count(1_500_000.0), "1.5M");
    }

    #[test]
    fn a_log_axis_always_has_two_readable_labels() {
        // Many decades on a tall plot: every decade.
        assert_eq!(
            log_labels(3e-7, 2e-2, 300.0),
            ["1e-6", "10e-6", "100e-6", "0.001", "0.01"]
        );
        // The same decades on a short plot (issue 37: no y numbers on a dirty scan at
        // 1280×720): every second decade or more, never none.
        let short = log_labels(3e-7, 2e-2, 60.0);
        assert!(short.len() >= 2 && short.len() <= 3, "{short:?}");
        // Inside one decade (a Hausdorff between 0.015 and 0.04): 2e-2 alone is not enough;
        // on a tall plot the 1-2-5 values, else the two ends.
        assert_eq!(log_labels(0.015, 0.04, 100.0).len(), 2);
        assert_eq!(log_labels(0.08, 0.3, 200.0), ["0.1", "0.2"]);
        // A range no round value fits (7.1 … 7.5): the two ends, two digits, never "7.3e0".
        let ends = log_labels(7.1, 7.5, 120.0);
        assert_eq!(ends.len(), 2, "{ends:?}");
        assert!(ends.iter().all(|l| !l.contains('e')), "{ends:?}");
        // Ticks are at least MIN_Y_LABEL_GAP apart on any plot height.
        for points in [40.0, 80.0, 160.0, 400.0] {
            for (lo, hi) in [(1e-9, 1.0), (0.01, 0.5), (3.0, 3.3), (1e-5, 2e-3)] {
                let (l, h) = (f64::log10(lo), f64::log10(hi));
                let marks: Vec<f64> = log_marks(GridInput {
                    bounds: (l, h),
                    base_step_size: (h - l) / points * f64::from(GRID_MIN_SPACING),
                })
                .into_iter()
                .filter(|m| is_labelled(m, &(l..=h)))
                .map(|m| m.value)
                .collect();
                assert!(marks.len() >= 2, "{lo}..{hi} at {points}: {marks:?}");
                let gap = marks
                    .windows(2)
                    .map(|w| (w[1] - w[0]) / (h - l) * points)
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    gap >= f64::from(MIN_Y_LABEL_GAP) - 1e-6 || marks.len() == 2,
                    "{lo}..{hi} at {points}: {gap} points apart"
                );
            }
        }
        // A single point gets MIN_LOG_SPAN decades around it.
        let (lo, hi) = log_y_range([0.73f64.log10()]).unwrap();
        assert!((hi - lo - MIN_LOG_SPAN).abs() < 1e-12);
    }

    #[test]
    fn the_signal_axis_shows_where_it_starts_and_ends() {
        let labels = |budget: f64, points: f64| -> Vec<String> {
            let (lo, hi) = (-0.05 * budget, 1.05 * budget);
            count_marks(
                GridInput {
                    bounds: (lo, hi),
                    base_step_size: (hi - lo) / points * f64::from(GRID_MIN_SPACING),
                },
                budget,
            )
            .into_iter()
            .map(|m| format_count(m.value))
            .collect()
        };
        assert_eq!(labels(150_000.0, 400.0), ["0", "50k", "100k", "150k"]);
        // The budget is labelled even when it is not a round value.
        assert_eq!(
            labels(190_000.0, 400.0),
            ["0", "50k", "100k", "150k", "190k"]
        );
        // A narrow plot: still both ends.
        let narrow = labels(87_900.0, 150.0);
        assert_eq!(narrow.first().unwrap(), "0");
        assert_eq!(narrow.last().unwrap(), "87.9k");
    }
}
