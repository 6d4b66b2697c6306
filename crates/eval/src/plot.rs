//! The sweep's error-versus-time plot as SVG (plotters' SVG backend, drawn into memory).
//!
//! Two panels, one per kind of row (their time axes differ):
//! - left, conversion rows: conversion seconds (x) against `surface_to_patch` RMS in % of
//!   the diagonal (y, lower is better);
//! - right, render rows: ms per frame (x) against image PSNR in dB (y, higher is better).
//!
//! Pareto-front points are filled red and joined in order of time; the others are hollow
//! grey. Every point is labelled with its setting.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::sweep::{cells_name, projection_name, RowKind, SweepResult, SweepRow};
use crate::EvalError;

const WIDTH: u32 = 1400;
const HEIGHT: u32 = 620;

fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> EvalError {
    EvalError::Plot(e.to_string())
}

/// One point of a panel.
struct Point {
    x: f64,
    y: f64,
    label: String,
    front: bool,
}

/// One panel's axes and points.
struct Panel {
    caption: String,
    x_desc: String,
    y_desc: String,
    points: Vec<Point>,
}

fn conversion_panel(result: &SweepResult) -> Panel {
    let points = rows_of(result, RowKind::Conversion)
        .map(|r| Point {
            x: r.convert_seconds,
            y: r.surface_to_patch.rms_rel * 100.0,
            label: format!("g{} c{} {}b", r.grid, r.cone_angle, r.width.bits()),
            front: r.on_front,
        })
        .collect();
    Panel {
        caption: "Conversion: error vs conversion time".to_owned(),
        x_desc: format!(
            "conversion seconds (median of {}, {} threads, file read excluded)",
            result.repeats, result.threads
        ),
        y_desc: "surface→patch RMS (% of diagonal), lower is better".to_owned(),
        points,
    }
}

fn render_panel(result: &SweepResult) -> Panel {
    let points = rows_of(result, RowKind::Render)
        .filter_map(|r| {
            let image = r.image?;
            Some(Point {
                x: r.render_ms?,
                // Identical images have no finite PSNR; plot them at the top of the range.
                y: image.psnr_db.unwrap_or(f64::INFINITY),
                label: format!(
                    "g{} {} {}",
                    r.grid,
                    r.projection.map_or("", projection_name),
                    r.cells.map_or("", cells_name)
                ),
                front: r.on_front,
            })
        })
        .collect();
    Panel {
        caption: "Rendering: image error vs frame time".to_owned(),
        x_desc: format!(
            "ms per frame ({}×{}, median over {} views, {} threads)",
            result.image_size[0], result.image_size[1], result.views, result.threads
        ),
        y_desc: "PSNR against the source's triangles (dB), higher is better".to_owned(),
        points,
    }
}

fn rows_of(result: &SweepResult, kind: RowKind) -> impl Iterator<Item = &SweepRow> {
    result.rows.iter().filter(move |r| r.kind == kind)
}

/// A padded range over `values` (finite ones), never empty.
fn padded(values: impl Iterator<Item = f64>, from_zero: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return (0.0, 1.0);
    }
    if from_zero {
        lo = lo.min(0.0);
    }
    let span = (hi - lo).max(hi.abs() * 0.1).max(1e-12);
    (
        if from_zero { lo } else { lo - 0.1 * span },
        hi + 0.15 * span,
    )
}

/// The chart of one panel: its axes and points.
type PanelChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, panel: &Panel) -> Result<(), EvalError> {
    // Time axes are not started at zero: the settings' times are close, and the tick labels
    // give the scale.
    let (x0, x1) = padded(panel.points.iter().map(|p| p.x), false);
    let (y0, y1) = padded(panel.points.iter().map(|p| p.y), false);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_desc.as_str())
        .y_desc(panel.y_desc.as_str())
        .axis_desc_style(("sans-serif", 13))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(plot_error)?;
    if panel.points.is_empty() {
        chart
            .draw_series(std::iter::once(Text::new(
                "no rows of this kind",
                (x0 + 0.3 * (x1 - x0), 0.5 * (y0 + y1)),
                ("sans-serif", 16),
            )))
            .map_err(plot_error)?;
        return Ok(());
    }
    let clamp_y = |y: f64| if y.is_finite() { y } else { y1 };
    draw_front(&mut chart, panel, clamp_y)?;
    draw_points(&mut chart, panel, clamp_y)?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(plot_error)?;
    Ok(())
}

/// Joins the panel's Pareto-front points in order of time (their `y` through `clamp_y`),
/// with its legend entry.
fn draw_front(
    chart: &mut PanelChart<'_, '_>,
    panel: &Panel,
    clamp_y: impl Fn(f64) -> f64,
) -> Result<(), EvalError> {
    let mut front: Vec<(f64, f64)> = panel
        .points
        .iter()
        .filter(|p| p.front)
        .map(|p| (p.x, clamp_y(p.y)))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front, RED.stroke_width(2)))
        .map_err(plot_error)?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    Ok(())
}

/// Draws every point of the panel (its `y` through `clamp_y`) with its label: filled red
/// on the front, hollow grey off it.
fn draw_points(
    chart: &mut PanelChart<'_, '_>,
    panel: &Panel,
    clamp_y: impl Fn(f64) -> f64,
) -> Result<(), EvalError> {
    chart
        .draw_series(panel.points.iter().map(|p| {
            let style = if p.front {
                RED.filled()
            } else {
                RGBColor(110, 110, 110).stroke_width(1)
            };
            EmptyElement::at((p.x, clamp_y(p.y)))
                + Circle::new((0, 0), 5, style)
                + Text::new(p.label.clone(), (7, -12), ("sans-serif", 11))
        }))
        .map_err(plot_error)?;
    Ok(())
}

/// The plot of `result` as an SVG document; `title` heads it (e.g. the source's name).
pub fn sweep_svg(result: &SweepResult, title: &str) -> Result<String, EvalError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let root = root.titled(title, ("sans-serif", 22)).map_err(plot_error)?;
        let (left, right) = root.split_horizontally(WIDTH / 2);
        draw_panel(&left, &conversion_panel(result))?;
        draw_panel(&right, &render_panel(result))?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padded_ranges_are_never_empty() {
        assert_eq!(padded(std::iter::empty(), true), (0.0, 1.0));
        let (lo, hi) = padded([5.0, 5.0].into_iter(), false);
        assert!(lo < 5.0 && hi > 5.0);
        let (lo, hi) = padded([1.0, f64::INFINITY, 3.0].into_iter(), true);
        assert_eq!(lo, 0.0);
        assert!(hi > 3.0 && hi.is_finite());
    }
}
