//! [`PerType`]: one value for each of the six shape types, indexed by [`ShapeType`].

use super::ShapeType;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;

/// One `T` per shape type; serialises as a map keyed by the type ids.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PerType<T>([T; 6]);

impl<T> PerType<T> {
    /// Builds the six values by calling `f` for each type in [`ShapeType::ALL`] order.
    pub fn from_fn(mut f: impl FnMut(ShapeType) -> T) -> Self {
        PerType(ShapeType::ALL.map(&mut f))
    }

    /// Like [`PerType::from_fn`], stopping at the first error.
    pub fn try_from_fn<E>(mut f: impl FnMut(ShapeType) -> Result<T, E>) -> Result<Self, E> {
        let mut out = Vec::with_capacity(6);
        for t in ShapeType::ALL {
            out.push(f(t)?);
        }
        match out.try_into() {
            Ok(array) => Ok(PerType(array)),
            // `out` holds exactly one value per type, so the conversion cannot fail.
            Err(_) => unreachable!("six shape types"),
        }
    }

    /// `(type, value)` pairs in canonical order.
    pub fn iter(&self) -> impl Iterator<Item = (ShapeType, &T)> {
        ShapeType::ALL.into_iter().zip(self.0.iter())
    }

    /// Applies `f` to every value.
    pub fn map<U>(&self, mut f: impl FnMut(ShapeType, &T) -> U) -> PerType<U> {
        PerType::from_fn(|t| f(t, &self[t]))
    }
}

impl<T> std::ops::Index<ShapeType> for PerType<T> {
    type Output = T;
    fn index(&self, t: ShapeType) -> &T {
        &self.0[t as usize]
    }
}

impl<T> std::ops::IndexMut<ShapeType> for PerType<T> {
    fn index_mut(&mut self, t: ShapeType) -> &mut T {
        &mut self.0[t as usize]
    }
}

impl<T: Serialize> Serialize for PerType<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.iter().map(|(t, v)| (t.id(), v)))
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for PerType<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let mut map: BTreeMap<String, T> = BTreeMap::deserialize(d)?;
        PerType::try_from_fn(|t| {
            map.remove(t.id())
                .ok_or_else(|| D::Error::custom(format!("missing shape type `{}`", t.id())))
        })
    }
}
