//! Monte Carlo estimators against exact results and the thesis' claims about them.

mod agreement;
mod proposition_2;
