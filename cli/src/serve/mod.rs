//! `vfd serve`: the service that polls a plant's buses (not built yet on this branch).

use crate::serve_args::ServeArgs;
use crate::Failure;

/// Runs the service for `args.plant`.
pub fn run(args: &ServeArgs) -> Result<(), Failure> {
    Err(Failure::new(format!(
        "vfd serve: not built yet ({} was not opened)",
        args.plant.display()
    ))
    .hint("`vfd serve --check PLANT` checks a plant file"))
}
