//! Event scripts: one event per line, for tests and screenshots.
//!
//! ```text
//! # comments and blank lines are skipped
//! orbit DX DY     drag of DX, DY pixels with the left button
//! pan DX DY       drag with the right button
//! zoom N          N wheel notches (negative: away)
//! view K          axis view of key K, 1..=6
//! reset           the automatic camera
//! shading | mode | mip | ssaa     the toggles of keys s, t, m, a
//! resize W H      the window's new size
//! ```

use crate::error::ViewError;
use crate::event::Event;
use crate::orbit::Axis;

/// The events of a script, in order.
pub fn parse_script(text: &str) -> Result<Vec<Event>, ViewError> {
    let mut events = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let event = parse_line(line).map_err(|problem| ViewError::Script {
            line: index + 1,
            problem,
        })?;
        events.push(event);
    }
    Ok(events)
}

/// One non-empty line.
fn parse_line(line: &str) -> Result<Event, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let args = &words[1..];
    let event = match words[0] {
        "orbit" => {
            let [dx, dy] = numbers(args)?;
            Event::Orbit { dx, dy }
        }
        "pan" => {
            let [dx, dy] = numbers(args)?;
            Event::Pan { dx, dy }
        }
        "zoom" => Event::Zoom(numbers::<1>(args)?[0]),
        "view" => {
            let [k] = numbers(args)?;
            let axis = (k.fract() == 0.0 && (1.0..=6.0).contains(&k))
                .then(|| Axis::of_key(k as u8))
                .flatten()
                .ok_or_else(|| format!("view takes a key 1..=6, found {k}"))?;
            Event::View(axis)
        }
        "resize" => {
            let [w, h] = numbers(args)?;
            let side = |v: f64| {
                (v.fract() == 0.0 && (1.0..=8192.0).contains(&v))
                    .then_some(v as u32)
                    .ok_or_else(|| format!("resize takes sides 1..=8192, found {v}"))
            };
            Event::Resize {
                width: side(w)?,
                height: side(h)?,
            }
        }
        word => no_argument_event(word, args)?,
    };
    Ok(event)
}

/// The events without arguments.
fn no_argument_event(word: &str, args: &[&str]) -> Result<Event, String> {
    let event = match word {
        "reset" => Event::Reset,
        "shading" => Event::CycleShading,
        "mode" => Event::ToggleMode,
        "mip" => Event::ToggleMip,
        "ssaa" => Event::ToggleSsaa,
        other => return Err(format!("unknown event {other:?}")),
    };
    if !args.is_empty() {
        return Err(format!("{word} takes no arguments"));
    }
    Ok(event)
}

/// Exactly `N` finite numbers.
fn numbers<const N: usize>(args: &[&str]) -> Result<[f64; N], String> {
    if args.len() != N {
        return Err(format!("expected {N} number(s), found {}", args.len()));
    }
    let mut out = [0.0; N];
    for (dst, word) in out.iter_mut().zip(args) {
        *dst = word
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{word:?} is not a finite number"))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_script_reads_every_event_and_skips_comments() {
        let text = "# start\norbit 10 -5\n\npan 1 2 # drag\nzoom -2\nview 3\nreset\nshading\nmode\nmip\nssaa\nresize 640 480\n";
        let events = parse_script(text).unwrap();
        assert_eq!(events.len(), 10);
        assert_eq!(events[0], Event::Orbit { dx: 10.0, dy: -5.0 });
        assert_eq!(events[2], Event::Zoom(-2.0));
        assert_eq!(events[3], Event::View(Axis::PosY));
        assert_eq!(
            events[9],
            Event::Resize {
                width: 640,
                height: 480
            }
        );
    }

    #[test]
    fn a_bad_line_names_its_number_and_problem() {
        for (text, needle) in [
            ("reset\nspin 3\n", "line 2: unknown event \"spin\""),
            ("orbit 1\n", "line 1: expected 2 number(s), found 1"),
            ("view 7\n", "line 1: view takes a key 1..=6"),
            ("zoom nan\n", "line 1: \"nan\" is not a finite number"),
            ("mip on\n", "line 1: mip takes no arguments"),
            ("resize 0 10\n", "line 1: resize takes sides"),
        ] {
            let err = parse_script(text).unwrap_err().to_string();
            assert!(err.contains(needle), "{err}");
        }
    }
}
