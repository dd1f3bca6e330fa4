//! Value parsers of the command line's options that are not knobs: sizes, colours, times,
//! frame ranges, bounded numbers and named choices. They are generic (a bounded number, any
//! [`Choice`]); a knob's value is parsed by its own declaration ([`super::knob_flags`]).

use clap::builder::{PossibleValue, TypedValueParser};
use lumen::choice::Choice;

/// Largest image side accepted on the command line (the adapter may allow less).
pub const MAX_SIDE: u32 = 16384;

/// Any [`Choice`] by name (its aliases accepted, not listed), with the names in `--help`
/// and in the error.
pub fn choice<T: Choice + Clone + Send + Sync>() -> ChoiceParser<T> {
    ChoiceParser(std::marker::PhantomData)
}

/// The value parser of [`choice`].
#[derive(Clone, Copy)]
pub struct ChoiceParser<T>(std::marker::PhantomData<fn() -> T>);

impl<T: Choice + Clone + Send + Sync> TypedValueParser for ChoiceParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<T, clap::Error> {
        T::parse(&value.to_string_lossy()).map_err(|e| invalid(cmd, arg, &e))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(T::NAMES.iter().map(|&n| PossibleValue::new(n))))
    }
}

/// A one-line usage error about `arg`'s value: `--ARG: message`.
pub fn invalid(cmd: &clap::Command, arg: Option<&clap::Arg>, message: &str) -> clap::Error {
    let flag = arg
        .and_then(clap::Arg::get_long)
        .map_or_else(String::new, |l| format!("--{l}: "));
    clap::Error::raw(
        clap::error::ErrorKind::InvalidValue,
        format!("{flag}{message}\n"),
    )
    .with_cmd(cmd)
}

/// A finite number in `min..=max`.
pub fn number(min: f32, max: f32) -> impl TypedValueParser<Value = f32> {
    move |s: &str| -> Result<f32, String> {
        let v = finite(s)?;
        if (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{s} is out of range: use {min}..={max}"))
        }
    }
}

/// A finite number.
pub fn finite(s: &str) -> Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("'{s}' is not a finite number"))
}

/// A finite number > 0.
pub fn positive(s: &str) -> Result<f32, String> {
    finite(s).and_then(|v| {
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{s} must be > 0"))
        }
    })
}

/// A finite number ≥ 0.
pub fn non_negative(s: &str) -> Result<f32, String> {
    finite(s).and_then(|v| {
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{s} must be ≥ 0"))
        }
    })
}

/// `on` or `off`.
pub fn on_off(s: &str) -> Result<bool, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("'{s}': expected on or off")),
    }
}

/// `WxH`, each side 1..=[`MAX_SIDE`].
pub fn size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH (e.g. 1280x720)"))?;
    let side = |v: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not WxH (e.g. 1280x720)"))?;
        if n == 0 || n > MAX_SIDE {
            return Err(format!("'{s}': each side must be 1..={MAX_SIDE}"));
        }
        Ok(n)
    };
    Ok((side(w)?, side(h)?))
}

/// `A..B` (frame numbers, A ≤ B).
pub fn frame_range(s: &str) -> Result<(u32, u32), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("'{s}' is not a frame range A..B (e.g. 0..47)"))?;
    let number = |x: &str| {
        x.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{x}' in '{s}' is not a frame number"))
    };
    let (a, b) = (number(a)?, number(b)?);
    if a > b {
        return Err(format!("frame range {s} runs backwards"));
    }
    Ok((a, b))
}

/// `R,G,B`, each finite and ≥ 0.
pub fn rgb(s: &str) -> Result<glam::Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not R,G,B (e.g. 1,1,1)"))?;
    match v[..] {
        [r, g, b] if v.iter().all(|c| c.is_finite() && *c >= 0.0) => Ok(glam::Vec3::new(r, g, b)),
        [_, _, _] => Err(format!("'{s}': each component must be a finite number ≥ 0")),
        _ => Err(format!("'{s}' is not R,G,B (e.g. 1,1,1)")),
    }
}

/// Seconds as a decimal or a fraction (`1/125`).
pub fn seconds(s: &str) -> Result<f32, String> {
    match s.split_once('/') {
        Some((n, d)) => {
            let (n, d) = (positive(n.trim())?, positive(d.trim())?);
            Ok(n / d)
        }
        None => positive(s),
    }
}

/// A focus distance in metres, or `inf`.
pub fn focus(s: &str) -> Result<f32, String> {
    if s.eq_ignore_ascii_case("inf") || s.eq_ignore_ascii_case("infinity") {
        return Ok(f32::INFINITY);
    }
    positive(s)
}

/// An exposure value at ISO 100 within the camera's range.
pub fn ev100(s: &str) -> Result<f32, String> {
    let (lo, hi) = lumen::scene::Exposure::EV100_RANGE;
    let v = finite(s)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("EV100 {s} is outside {lo}..={hi}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse<P: TypedValueParser>(p: &P, s: &str) -> Result<P::Value, clap::Error> {
        p.parse_ref(&clap::Command::new("t"), None, std::ffi::OsStr::new(s))
    }

    #[test]
    fn sizes() {
        assert_eq!(size("1280x720"), Ok((1280, 720)));
        assert_eq!(size("64X32"), Ok((64, 32)));
        for bad in ["0x10", "10x0", "x", "12", "-1x5", "axb", "99999x1", ""] {
            assert!(size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn colours_and_ranges() {
        assert_eq!(rgb("1, 0.5,2"), Ok(glam::Vec3::new(1.0, 0.5, 2.0)));
        for bad in ["1,2", "1,2,3,4", "a,b,c", "-1,0,0", "nan,0,0", ""] {
            assert!(rgb(bad).is_err(), "{bad}");
        }
        assert!(parse(&number(0.0, 1.0), "1.5").is_err());
        assert_eq!(parse(&number(0.0, 1.0), "0.3").ok(), Some(0.3));
        assert!(non_negative("-2").is_err());
        assert!(finite("inf").is_err());
    }

    #[test]
    fn camera_values() {
        assert_eq!(seconds("1/125"), Ok(0.008));
        assert_eq!(seconds("0.5"), Ok(0.5));
        assert!(seconds("1/0").is_err() && seconds("-1").is_err());
        assert_eq!(focus("inf"), Ok(f32::INFINITY));
        assert!(focus("0").is_err());
        assert_eq!(ev100("-2.5"), Ok(-2.5));
        assert!(ev100("nan").is_err());
        assert!(ev100("45").is_err());
    }

    #[test]
    fn choices_take_names_and_aliases() {
        use lumen::shading::color::Tonemapper;
        assert_eq!(
            parse(&choice::<Tonemapper>(), "aces").ok(),
            Some(Tonemapper::AcesFitted)
        );
        let err = parse(&choice::<Tonemapper>(), "filmic").expect_err("unknown");
        assert!(err.to_string().contains("pbr-neutral"), "{err}");
    }

    #[test]
    fn frame_ranges() {
        assert_eq!(frame_range("0..3"), Ok((0, 3)));
        assert_eq!(frame_range("5..5"), Ok((5, 5)));
        assert!(frame_range("3..0").unwrap_err().contains("backwards"));
        assert!(frame_range("0-3").unwrap_err().contains("A..B"));
        assert!(frame_range("a..3").unwrap_err().contains("'a'"));
    }
}
