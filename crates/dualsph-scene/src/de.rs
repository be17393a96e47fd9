//! Serde helpers the parts of a scene share: identifiers read as strings and integers read
//! so that a float or a string is refused at its own position.

use serde::de::{self, DeserializeSeed, Deserializer, Visitor};
use std::fmt;

/// Deserializes an identifier (a struct field or enum variant name) as an owned string.
pub(crate) struct Ident;

impl<'de> DeserializeSeed<'de> for Ident {
    type Value = String;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
        d.deserialize_identifier(IdentVisitor)
    }
}

struct IdentVisitor;

impl Visitor<'_> for IdentVisitor {
    type Value = String;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an identifier")
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<String, E> {
        Ok(v.to_owned())
    }
}

/// Integer fields read through `deserialize_any`, so a float or a string is reported as "expected
/// a non-negative integer" at its own position (ron's typed integer parser would stop at the
/// `.` of `2.5` and complain about a missing comma instead).
pub(crate) mod int {
    use serde::de::{self, Deserializer, Unexpected, Visitor};
    use std::fmt;
    use std::marker::PhantomData;

    struct Int;

    impl Visitor<'_> for Int {
        type Value = u64;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a non-negative integer")
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<u64, E> {
            Ok(v)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<u64, E> {
            u64::try_from(v).map_err(|_| E::invalid_value(Unexpected::Signed(v), &self))
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<u64, E> {
            Err(E::invalid_type(Unexpected::Float(v), &self))
        }
    }

    /// A non-negative integer that fits `T`.
    pub(crate) fn de<'de, D: Deserializer<'de>, T: TryFrom<u64>>(d: D) -> Result<T, D::Error> {
        let v = d.deserialize_any(Int)?;
        T::try_from(v).map_err(|_| de::Error::custom(format!("integer {v} is out of range")))
    }

    struct OptInt<T>(PhantomData<T>);

    impl<'de, T: TryFrom<u64>> Visitor<'de> for OptInt<T> {
        type Value = Option<T>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("`None` or a non-negative integer")
        }
        fn visit_none<E: de::Error>(self) -> Result<Option<T>, E> {
            Ok(None)
        }
        fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Option<T>, D::Error> {
            de(d).map(Some)
        }
    }

    /// `None`, `Some(n)` or (implicitly) `n`.
    pub(crate) fn de_opt<'de, D: Deserializer<'de>, T: TryFrom<u64>>(
        d: D,
    ) -> Result<Option<T>, D::Error> {
        d.deserialize_option(OptInt(PhantomData))
    }
}
