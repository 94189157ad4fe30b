//! Typed element ids: a leaf module, since errors and meshes both name elements by them
//! (`crate::mesh` re-exports them).

use std::fmt;

macro_rules! define_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, serde::Serialize, bytemuck::Pod, bytemuck::Zeroable)]
        #[repr(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The id that names no element.
            pub const INVALID: $name = $name(u32::MAX);

            /// The id as an array index.
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// Whether this id names an element.
            pub fn is_valid(self) -> bool {
                self != Self::INVALID
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                if self.is_valid() { write!(f, "#{}", self.0) } else { write!(f, "#invalid") }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Debug::fmt(self, f)
            }
        }
    };
}

define_id!(
    /// Index of a vertex in a [`crate::Mesh`].
    VertexId
);
define_id!(
    /// Index of a triangle in a [`crate::Mesh`].
    FaceId
);
