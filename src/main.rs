/// mimalloc rather than the system's allocator: loading and building a 100k-triangle mesh
/// allocates and frees tens of megabytes of short-lived buffers, and glibc's allocator handed
/// each big one back to the kernel, so a fifth of that time went to page faults on fresh pages.
///
/// Built with `no_thp`: mimalloc no longer asks the kernel for transparent huge pages
/// (`madvise`) on its memory. With them, the kernel cleared each 2 MB page whole when it was
/// first touched: the bunny at 1024² held 47 MB to use 13, and 19 MB without them
/// (docs/performance.md). Where the system gives huge pages to every program unasked, it still
/// does.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    raycast::cli::run(std::env::args_os().skip(1).collect())
}
