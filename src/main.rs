//! The `sinew` binary: see `sinew --help`.

fn main() -> std::process::ExitCode {
    sinew::cli::run(std::env::args_os())
}
