//! Link options for the shipped binary.

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    // Identical code folding: monomorphized generics often compile to the same machine code (one
    // function for two types of one layout, for two closures doing the same thing), and the
    // linker keeps one copy. It takes 0.6 MB off the release binary (docs/src/budgets.md).
    // "all" rather than "safe": "safe" folded nothing here, and Rust promises no distinct
    // addresses for distinct functions (`std::ptr::fn_addr_eq`); "all" also merges identical
    // read-only data, which none of our outputs changed with. Only where rustc links with
    // its own LLD (x86-64 Linux since Rust 1.90): other linkers do not know the option. Release
    // builds only: the link takes longer and the test builds gain nothing from it.
    let var = |name: &str| std::env::var(name).unwrap_or_default();
    let lld_by_default = var("CARGO_CFG_TARGET_ARCH") == "x86_64"
        && var("CARGO_CFG_TARGET_OS") == "linux"
        && var("CARGO_CFG_TARGET_ENV") == "gnu";
    // A build that chooses its own linker (RUSTFLAGS `-C linker...`, or `target.*.linker` in a
    // cargo config, which cargo passes here as RUSTC_LINKER) may not have LLD.
    let own_linker =
        var("CARGO_ENCODED_RUSTFLAGS").contains("link") || !var("RUSTC_LINKER").is_empty();
    if var("PROFILE") == "release" && lld_by_default && !own_linker {
        println!("cargo::rustc-link-arg-bins=-Wl,--icf=all");
    }
}
