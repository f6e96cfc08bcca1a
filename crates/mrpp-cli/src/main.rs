//! The `mrpp` binary: the command line lives in the library ([`mrpp_cli::main`]).

fn main() -> std::process::ExitCode {
    mrpp_cli::main()
}
