//! The `motion-stylizer` command-line tool. (Subcommands being written.)
fn main() {}
