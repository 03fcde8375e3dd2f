//! The dispatch on a run-time number of joints onto the const-generic core, written once: the
//! joint counts 1 to [`MAX_JOINTS`](super::MAX_JOINTS) are listed in one place
//! ([`dof_dispatch!`](crate::dof_dispatch)), and every run-time dispatch expands from it:
//! [`with_dof!`](crate::with_dof) (a number), [`dof_enum!`](crate::dof_enum) (an enum with a
//! variant per number of joints) and [`on_joints!`](crate::on_joints) (a match on such an
//! enum).

/// The one list of the joint counts dispatched at run time (1 to 8, each with its variant's
/// name), and the expansions of [`with_dof!`](crate::with_dof),
/// [`dof_enum!`](crate::dof_enum) and [`on_joints!`](crate::on_joints) over it.
#[doc(hidden)]
#[macro_export]
macro_rules! dof_dispatch {
    (@list $($rest:tt)*) => {
        $crate::dof_dispatch! { @go [J1 1, J2 2, J3 3, J4 4, J5 5, J6 6, J7 7, J8 8] $($rest)* }
    };
    (@go [$($v:ident $n:literal),*] number $x:expr, $N:ident => $body:expr, otherwise $other:expr) => {
        match $x {
            $($n => {
                #[allow(dead_code)]
                const $N: usize = $n;
                $body
            })*
            _ => $other,
        }
    };
    (@go [$($v:ident $n:literal),*] variant $enum:ident, $self:expr, $c:ident, $N:ident => $body:expr) => {
        match $self {
            $($enum::$v($c) => {
                #[allow(dead_code)]
                const $N: usize = $n;
                $body
            })*
        }
    };
    (@go [$($v:ident $n:literal),*] enum $(#[$m:meta])* $vis:vis $name:ident of $ty:ident) => {
        $(#[$m])*
        // Each variant on the heap: the values are large (a controller with its obstacle
        // set's fixed capacity, ~8 KB for 6 joints), and inline they took a slot per variant
        // on the stack of the functions that build, clone or convert one.
        $vis enum $name {
            $(
                #[doc = concat!("With ", stringify!($n), " joints.")]
                $v(Box<$ty<$n>>),
            )*
        }

        $(
            impl From<$ty<$n>> for $name {
                fn from(x: $ty<$n>) -> Self {
                    $name::$v(Box::new(x))
                }
            }

            impl TryFrom<&$name> for $ty<$n> {
                type Error = $crate::SimError;

                /// The value, when it has this number of joints.
                fn try_from(x: &$name) -> $crate::Result<Self> {
                    match x {
                        $name::$v(c) => Ok(c.as_ref().clone()),
                        #[allow(unreachable_patterns)]
                        _ => Err($crate::SimError::Core(
                            pvfc_core::Error::new(
                                pvfc_core::ErrorKind::DimensionMismatch,
                                concat!(stringify!($name), ": another number of joints"),
                            )
                            .with_value($n as f64),
                        )),
                    }
                }
            }
        )*
    };
}

/// Runs `$body` with `$n` (a run-time number of joints, 1…8) as the const generic `$N`;
/// evaluates `$otherwise` for any other number.
#[macro_export]
macro_rules! with_dof {
    ($n:expr, $N:ident => $body:expr, otherwise $otherwise:expr) => {
        $crate::dof_dispatch!(@list number $n, $N => $body, otherwise $otherwise)
    };
}

/// Defines an enum with one variant per number of joints, `J1(Box<T<1>>)` …
/// `J8(Box<T<8>>)`, for a generic type `T<const N: usize>` (a type alias when the type has
/// other parameters), with `From<T<N>>` for the enum and `TryFrom<&Enum>` for `T<N>` (an error
/// unless the value has `N` joints).
#[macro_export]
macro_rules! dof_enum {
    ($(#[$m:meta])* $vis:vis enum $name:ident of $ty:ident) => {
        $crate::dof_dispatch!(@list enum $(#[$m])* $vis $name of $ty);
    };
}

/// Runs `$body` on the variant of an enum made by [`dof_enum!`](crate::dof_enum), with `$c`
/// the variant's value and `$N` its number of joints as a constant.
#[macro_export]
macro_rules! on_joints {
    ($enum:ident, $self:expr, $c:ident, $N:ident => $body:expr) => {
        $crate::dof_dispatch!(@list variant $enum, $self, $c, $N => $body)
    };
}
