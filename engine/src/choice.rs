//! Closed sets of named values: the enums a knob, a command-line option or a file chooses
//! from (a shadow filter, a tone mapper, a debug view, …).
//!
//! [`choices!`] declares such an enum once, with the name each variant has
//! outside Rust, and derives from that one list what every front end needs: the ordered
//! list of values ([`Choice::ALL`]), the names ([`Choice::NAMES`], [`Choice::name`]), the
//! parser ([`Choice::from_name`], whose error lists the names), `Display`, and serde's
//! `Serialize`/`Deserialize` as the name. No enum writes that trio by hand.

/// An enum whose values have names (declared with [`choices!`]).
pub trait Choice: Copy + Eq + Sized + 'static {
    /// What the values are, in a few words, for error messages ("shadow filter").
    const WHAT: &'static str;
    /// Every value, in declaration order.
    const ALL: &'static [Self];
    /// Every value's name, in the same order.
    const NAMES: &'static [&'static str];
    /// Other names [`Choice::from_name`] accepts (older or longer spellings), not listed.
    const ALIASES: &'static [(&'static str, Self)] = &[];

    /// The value's name.
    fn name(self) -> &'static str {
        let i = Self::ALL.iter().position(|v| *v == self).unwrap_or(0);
        Self::NAMES[i]
    }

    /// The value called `name` (ASCII case ignored).
    fn from_name(name: &str) -> Option<Self> {
        let name = name.trim();
        Self::NAMES
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|i| Self::ALL[i])
            .or_else(|| {
                Self::ALIASES
                    .iter()
                    .find(|(n, _)| n.eq_ignore_ascii_case(name))
                    .map(|(_, v)| *v)
            })
    }

    /// The value called `name`, or an error that lists the names.
    fn parse(name: &str) -> Result<Self, String> {
        Self::from_name(name).ok_or_else(|| {
            format!(
                "unknown {} '{name}' (use {})",
                Self::WHAT,
                Self::NAMES.join(", ")
            )
        })
    }
}

/// Declares an enum whose variants have names outside Rust, and implements [`Choice`],
/// `Display` and serde's traits for it (as the name).
///
/// ```
/// lumen::choice::choices! {
///     /// How a thing is filtered.
///     #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
///     pub enum Filter: "filter" {
///         /// One tap.
///         #[default]
///         Nearest = "nearest",
///         /// Four taps.
///         Bilinear = "bilinear",
///     }
/// }
/// use lumen::choice::Choice;
/// assert_eq!(Filter::from_name("Bilinear"), Some(Filter::Bilinear));
/// assert_eq!(Filter::Nearest.to_string(), "nearest");
/// assert!(Filter::parse("cubic").unwrap_err().contains("nearest, bilinear"));
/// ```
///
/// A variant may give its discriminant before its name (`Tent(3) = "tent"`), for enums
/// whose values are shader constants, and other accepted spellings after it
/// (`= "metal-rough" | "metal-roughness"`).
#[doc(hidden)]
#[macro_export]
macro_rules! __choices {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident : $what:literal {
            $(
                $(#[$vmeta:meta])*
                $variant:ident $(($disc:literal))? = $label:literal $(| $alias:literal)*
            ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis enum $name {
            $(
                $(#[$vmeta])*
                $variant $(= $disc)?,
            )+
        }

        impl $crate::choice::Choice for $name {
            const WHAT: &'static str = $what;
            const ALL: &'static [Self] = &[$($name::$variant),+];
            const NAMES: &'static [&'static str] = &[$($label),+];
            const ALIASES: &'static [(&'static str, Self)] = &[$($(($alias, $name::$variant),)*)+];
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str($crate::choice::Choice::name(*self))
            }
        }

        impl $crate::choice::serde::Serialize for $name {
            fn serialize<S: $crate::choice::serde::Serializer>(
                &self,
                serializer: S,
            ) -> ::std::result::Result<S::Ok, S::Error> {
                serializer.serialize_str($crate::choice::Choice::name(*self))
            }
        }

        impl<'de> $crate::choice::serde::Deserialize<'de> for $name {
            fn deserialize<D: $crate::choice::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<Self, D::Error> {
                let name = <::std::string::String as $crate::choice::serde::Deserialize>::deserialize(deserializer)?;
                <$name as $crate::choice::Choice>::parse(&name)
                    .map_err(<D::Error as $crate::choice::serde::de::Error>::custom)
            }
        }
    };
}

#[doc(inline)]
pub use crate::__choices as choices;

#[doc(hidden)]
pub use serde;

#[cfg(test)]
mod tests {
    use super::Choice;

    crate::choice::choices! {
        /// A test set.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        enum Shape: "shape" {
            /// Round.
            Circle(4) = "circle",
            /// Four corners.
            Square(1) = "square" | "box" | "quad",
        }
    }

    #[test]
    fn names_round_trip_and_keep_discriminants() {
        for &s in Shape::ALL {
            assert_eq!(Shape::from_name(s.name()), Some(s));
            assert_eq!(Shape::parse(&s.to_string()), Ok(s));
        }
        assert_eq!(Shape::Circle as u32, 4);
        assert_eq!(Shape::Square as u32, 1);
        assert_eq!(Shape::from_name(" SQUARE "), Some(Shape::Square));
        assert_eq!(Shape::from_name("quad"), Some(Shape::Square));
        assert_eq!(
            Shape::parse("hexagon"),
            Err("unknown shape 'hexagon' (use circle, square)".into())
        );
    }

    #[test]
    fn serde_uses_the_names() {
        assert_eq!(
            serde_json::to_string(&Shape::Square).expect("serialise"),
            "\"square\""
        );
        let parsed: Shape = serde_json::from_str("\"circle\"").expect("deserialise");
        assert_eq!(parsed, Shape::Circle);
        let err = serde_json::from_str::<Shape>("\"oval\"").expect_err("unknown");
        assert!(err.to_string().contains("use circle, square"), "{err}");
    }
}
