//! The oracles by name, as one value: what front ends build from a user's choice.

use crate::error::{ErrorKind, Result, token};
use crate::hierarchy::kernel::{KernelSamples, Visibility};
use crate::hierarchy::oracle::{
    Decision, KernelAverageOracle, KernelSmoothnessOracle, MiIncreaseOracle,
    MutualInformationOracle, Oracle, Pair, PowerOracle, RegularOracle,
};

/// The names [`OracleChoice3::new`] accepts.
#[cfg(test)]
pub(crate) const ORACLE_NAMES: [&str; 6] = ["power", "ks", "ks-av", "mi", "mi-increase", "regular"];

/// Most splits per patch of the regular mesh (`4⁸ = 65 536` elements a patch).
pub(crate) const MAX_REGULAR_LEVEL: u32 = 8;

/// Any of the oracles of the hierarchy (power, KS, KS-av, MI, MI increase, regular), chosen
/// by name with [`OracleChoice3::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OracleChoice3(Choice);

/// The oracle an [`OracleChoice3`] holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Choice {
    /// (2.48).
    Power(PowerOracle),
    /// (2.49).
    KernelSmoothness(KernelSmoothnessOracle),
    /// (2.50).
    KernelAverage(KernelAverageOracle),
    /// (6.29)–(6.30).
    MutualInformation(MutualInformationOracle),
    /// (6.3)–(6.5).
    MiIncrease(MiIncreaseOracle),
    /// The regular mesh.
    Regular(RegularOracle),
}

impl OracleChoice3 {
    /// The oracle called `name` (`power`, `ks`, `ks-av`, `mi`, `mi-increase` or `regular`) with threshold `epsilon`; for
    /// `regular`, `epsilon` is the number of splits per patch (an integer from 0 to
    /// `MAX_REGULAR_LEVEL`).
    ///
    /// # Errors
    /// [`ErrorKind::UnknownOracle`] for another name; [`ErrorKind::BadParameter`] for a
    /// negative or non-finite `epsilon`, or a level that is not such an integer.
    pub fn new(name: &str, epsilon: f64) -> Result<Self> {
        check_epsilon(epsilon)?;
        Ok(Self(match name {
            "power" => Choice::Power(PowerOracle { epsilon }),
            "ks" => Choice::KernelSmoothness(KernelSmoothnessOracle { epsilon }),
            "ks-av" => Choice::KernelAverage(KernelAverageOracle { epsilon }),
            "mi" => Choice::MutualInformation(MutualInformationOracle { epsilon }),
            "mi-increase" => Choice::MiIncrease(MiIncreaseOracle {
                epsilon,
                gradient: MiIncreaseOracle::DEFAULT_GRADIENT,
            }),
            "regular" => {
                if epsilon > f64::from(MAX_REGULAR_LEVEL) || f64::from(epsilon as u32) != epsilon {
                    return Err(ErrorKind::BadParameter {
                        name: "regular level (0 to 8)",
                        value: epsilon,
                    }
                    .into());
                }
                Choice::Regular(RegularOracle {
                    level: epsilon as u32,
                })
            }
            _ => return Err(ErrorKind::UnknownOracle(token(name)).into()),
        }))
    }

    /// The oracle's name, as [`OracleChoice3::new`] takes it.
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.inner().name()
    }

    fn inner(&self) -> &dyn Oracle {
        match &self.0 {
            Choice::Power(o) => o,
            Choice::KernelSmoothness(o) => o,
            Choice::KernelAverage(o) => o,
            Choice::MutualInformation(o) => o,
            Choice::MiIncrease(o) => o,
            Choice::Regular(o) => o,
        }
    }
}

impl Oracle for OracleChoice3 {
    fn name(&self) -> &'static str {
        self.inner().name()
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, vis: &dyn Visibility) -> Decision {
        self.inner().decide(pair, s, vis)
    }
}

/// Refuses an oracle threshold that is not finite and `≥ 0` (`BadParameter` `"epsilon"`),
/// for the oracles of [`OracleChoice3`] and of the Monte Carlo hierarchy alike.
pub(crate) fn check_epsilon(epsilon: f64) -> Result<()> {
    if epsilon.is_finite() && epsilon >= 0.0 {
        Ok(())
    } else {
        Err(ErrorKind::BadParameter {
            name: "epsilon",
            value: epsilon,
        }
        .into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_input_is_typed() {
        for name in ORACLE_NAMES {
            assert_eq!(OracleChoice3::new(name, 2.0).unwrap().name(), name);
        }
        assert!(matches!(
            OracleChoice3::new("gradient", 1.0).unwrap_err().kind(),
            ErrorKind::UnknownOracle(_)
        ));
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            assert!(matches!(
                OracleChoice3::new("mi", bad).unwrap_err().kind(),
                ErrorKind::BadParameter { .. }
            ));
        }
        assert!(OracleChoice3::new("regular", 1.5).is_err());
        assert!(OracleChoice3::new("regular", 9.0).is_err());
    }
}
