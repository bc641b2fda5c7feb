fn main() -> std::process::ExitCode {
    raycast::cli::run(std::env::args_os().skip(1).collect())
}
