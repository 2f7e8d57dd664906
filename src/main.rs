//! The `motion-stylizer` command-line tool (native only: on wasm32 the crate is the npm package's
//! library, and this binary is an empty stub so that `cargo test --target wasm32-unknown-unknown`
//! builds).

#[cfg(not(target_arch = "wasm32"))]
mod cli;

#[cfg(not(target_arch = "wasm32"))]
use clap::Parser;
#[cfg(not(target_arch = "wasm32"))]
use std::process::ExitCode;

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> ExitCode {
    // Training and batched inference free and reallocate multi-megabyte buffers every step.
    motion_stylizer::memory::keep_freed_memory();
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
