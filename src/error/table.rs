//! `named_table!`: an enum of plain names declared from one table of variant → name, so that
//! each name is stated once ([`ErrorKind`](super::ErrorKind), [`Parameter`](super::Parameter)).

/// Declares a `#[non_exhaustive]` enum of plain variants from a table `Variant => "name",`,
/// with `ALL` (every variant, in the table's order), `as_str` (its name) and `Display` (the
/// same name).
macro_rules! named_table {
    (
        $(#[$meta:meta])*
        pub enum $ty:ident {
            $($(#[$doc:meta])* $variant:ident => $name:literal,)*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum $ty {
            $($(#[$doc])* $variant,)*
        }

        impl $ty {
            #[doc = concat!("Every `", stringify!($ty), "`, each once, in the order of the table.")]
            pub const ALL: &'static [$ty] = &[$($ty::$variant,)*];

            /// Its name, as messages and JSON print it.
            ///
            /// # Examples
            /// ```
            #[doc = concat!("use bearing_ident::", stringify!($ty), ";")]
            #[doc = concat!("let first = ", stringify!($ty), "::ALL[0];")]
            /// assert_eq!(first.to_string(), first.as_str());
            /// assert!(!first.as_str().is_empty());
            /// ```
            pub const fn as_str(self) -> &'static str {
                match self {
                    $($ty::$variant => $name,)*
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

pub(super) use named_table;

#[cfg(test)]
mod tests {
    use super::super::{ErrorKind, Parameter};

    /// Every name of a table once, and `Display` the name.
    fn distinct_and_displayed<T: Copy + std::fmt::Display>(all: &[T], name: fn(T) -> &'static str) {
        let mut names: Vec<&str> = all.iter().map(|&v| name(v)).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len(), "two variants share a name");
        for &v in all {
            assert_eq!(v.to_string(), name(v));
        }
    }

    #[test]
    fn every_table_names_each_variant_once() {
        distinct_and_displayed(ErrorKind::ALL, ErrorKind::as_str);
        distinct_and_displayed(Parameter::ALL, Parameter::as_str);
    }
}
