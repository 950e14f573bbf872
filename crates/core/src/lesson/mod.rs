//! The classroom's material: the worked example (powers 2, 5, 20 at a shading point whose
//! contributions are 1, 2, 15), the walkthrough's steps with live numbers, Vose's
//! construction recorded step by step, the estimator run at one shading point, one point
//! inspected light by light, one spatial pick recorded node by node ([`tree_pick`]), and
//! numbers shown as exact fractions.

pub mod construction;
pub mod fraction;
pub mod inspect;
pub mod point_estimate;
pub mod tree_pick;
pub mod walkthrough;
pub mod worked_example;
