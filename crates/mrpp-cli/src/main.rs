//! The `mrpp` binary: the command line lives in the library ([`mrpp_cli::main`]).

/// Counts live heap bytes, so that `--memory-limit` can stop every planner (`mrpp_core::memory`).
#[global_allocator]
static ALLOC: mrpp_core::memory::CountingAlloc = mrpp_core::memory::CountingAlloc;

fn main() -> std::process::ExitCode {
    mrpp_cli::main()
}
