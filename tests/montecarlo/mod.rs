//! Monte Carlo estimators against exact results and the thesis' claims about them.

mod agreement;
mod bundles;
mod bundles3d;
mod occluded3d;
mod proposition_2;
