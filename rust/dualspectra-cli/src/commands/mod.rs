//! One module per subcommand: an `Args` (clap derive) and `run(Args) -> Result<(), CliError>`.
//! Commands convert and call the core; no formula lives here.

pub mod curvature;
pub mod spectrum;
pub mod bench;
pub mod demo;
pub mod index;
pub mod localize;
pub mod prepare;
pub mod search;
pub mod similarity;
