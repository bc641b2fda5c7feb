/// mimalloc rather than the system's allocator: loading and building a 100k-triangle mesh
/// allocates and frees tens of megabytes of short-lived buffers, and glibc's allocator handed
/// each big one back to the kernel, so a fifth of that time went to page faults on fresh pages.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    raycast::cli::run(std::env::args_os().skip(1).collect())
}
