//! The SVG chart of a run: Motor_Position, speed and a strip of status bits over time.

use std::fmt;
use std::path::Path;

use plotters::prelude::*;

use super::{Sample, Shown, Trace};
use crate::smd::indexer::{stat0, stat1};
use crate::smd::plot::{format_tick, PlotError};

/// The bits the chart's strip shows, top first: (name, STATUS word 0 or 1, mask).
const LANES: [(&str, u8, u16); 11] = [
    ("Moving_CW", 0, stat0::MOVING_CW),
    ("Moving_CCW", 0, stat0::MOVING_CCW),
    ("Accelerating", 0, stat0::ACCELERATING),
    ("Decelerating", 0, stat0::DECELERATING),
    ("In_Hold_State", 0, stat0::IN_HOLD_STATE),
    ("Move_Complete", 0, stat0::MOVE_COMPLETE),
    ("Position_Invalid", 0, stat0::POSITION_INVALID),
    ("Input_Error", 0, stat0::INPUT_ERROR),
    ("Command_Error", 0, stat0::COMMAND_ERROR),
    ("IN1_Active", 1, stat1::IN1_ACTIVE),
    ("IN2_Active", 1, stat1::IN2_ACTIVE),
];

/// A y range around `values` with 5 % room, never empty.
fn y_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi <= lo {
        hi = lo + 1.0;
    }
    let pad = (hi - lo) * 0.05;
    (lo - pad)..(hi + pad)
}

/// Draws `trace` to `path` as SVG: three panels over time — Motor_Position, speed, and a strip of
/// status bits (Moving_CW … IN2_Active, a filled bar while the bit is 1).
pub fn plot(trace: &Trace, path: &Path) -> Result<(), PlotError> {
    let err = |e: &dyn fmt::Display| PlotError::at(path, e);
    let x = 0.0..trace.until.as_secs_f64();
    let pts = |f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        trace
            .curve
            .iter()
            .map(|s| (s.time.as_secs_f64(), f(s)))
            .collect()
    };
    let position = pts(&|s| f64::from(s.inputs.motor_position));
    let speed = pts(&|s| s.speed);

    let root = SVGBackend::new(path, (1000, 960)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root
        .titled(
            &format!("smd simulate {} (cycle {})", trace.file, Shown(trace.cycle)),
            ("sans-serif", 22),
        )
        .map_err(|e| err(&e))?;
    let (top, rest) = root.split_vertically(320);
    let (middle, bottom) = rest.split_vertically(260);
    let label_area = 150;

    for (area, values, y_desc, colour) in [
        (&top, &position, "Motor_Position [steps]", BLUE),
        (&middle, &speed, "speed [steps/s]", RED),
    ] {
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .margin_right(24)
            .x_label_area_size(30)
            .y_label_area_size(label_area)
            .build_cartesian_2d(x.clone(), y_range(values.iter().map(|p| p.1)))
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .y_desc(y_desc)
            .x_label_formatter(&|v| format_tick(*v))
            .y_label_formatter(&|v| format_tick(*v))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(|e| err(&e))?;
        chart
            .draw_series(LineSeries::new(
                values.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
    }

    let n = LANES.len();
    // Lane k (top first) spans 10 units of y: its baseline at 10·(n − 1 − k), its bar 7 high, its name
    // at the middle of the bar (integer coordinates, whose key points plotters can format).
    let lane_y = |k: usize| 10 * (n - 1 - k) as i32;
    let keys: Vec<i32> = (0..n).map(|k| lane_y(k) + 3).collect();
    let mut chart = ChartBuilder::on(&bottom)
        .margin(10)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(label_area)
        .build_cartesian_2d(x.clone(), (-2..10 * n as i32).with_key_points(keys))
        .map_err(|e| err(&e))?;
    let lane_name = |v: &i32| -> String {
        let k = (v - 3) / 10;
        if (0..n as i32).contains(&k) && (v - 3) % 10 == 0 {
            LANES[n - 1 - k as usize].0.to_string()
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc("time [s]")
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&lane_name)
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    let colours = [
        BLUE, BLUE, GREEN, RED, MAGENTA, BLACK, RED, RED, RED, CYAN, CYAN,
    ];
    let end = x.end;
    for (k, &(_, word, mask)) in LANES.iter().enumerate() {
        let y = lane_y(k);
        let colour = colours[k];
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(0.0, y), (end, y)],
                BLACK.mix(0.3),
            )))
            .map_err(|e| err(&e))?;
        let on = |s: &Sample| {
            let w = if word == 0 {
                s.inputs.status0
            } else {
                s.inputs.status1
            };
            w & mask != 0
        };
        let mut bars = Vec::new();
        let mut since: Option<f64> = None;
        for s in &trace.curve {
            let t = s.time.as_secs_f64();
            match (on(s), since) {
                (true, None) => since = Some(t),
                (false, Some(t0)) => {
                    bars.push((t0, t));
                    since = None;
                }
                _ => {}
            }
        }
        if let Some(t0) = since {
            bars.push((t0, end));
        }
        chart
            .draw_series(
                bars.into_iter().map(|(t0, t1)| {
                    Rectangle::new([(t0, y), (t1, y + 7)], colour.mix(0.6).filled())
                }),
            )
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
