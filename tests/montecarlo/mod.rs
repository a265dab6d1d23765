//! Monte Carlo estimators against exact results and the thesis' claims about them.

mod agreement;
mod bundles;
mod proposition_2;
