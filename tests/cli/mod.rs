//! The command line: usage errors, every flag's effect, the README's examples, and
//! interruption (signals and progress callbacks).

mod flags;
mod interrupt;
mod readme;
mod simplify_plan;
mod usage;
