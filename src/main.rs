fn main() {
    asperity::memory::return_large_buffers_to_the_os();
    std::process::exit(asperity::cli::run());
}
