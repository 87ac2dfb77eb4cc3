//! `mpm`: run, check and play scene files from the command line.

#[cfg(not(target_arch = "wasm32"))]
mod cli;
#[cfg(not(target_arch = "wasm32"))]
mod play;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main(play::play)
}

#[cfg(target_arch = "wasm32")]
fn main() {}
