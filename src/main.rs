fn main() {
    std::process::exit(asperity::cli::run());
}
