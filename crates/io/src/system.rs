//! What the machine has: the default memory budget of `core::budget`.

/// Physical memory in bytes (`MemTotal` of `/proc/meminfo`), if the system says.
pub fn physical_memory_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The default budget: half the physical memory, or `core::budget`'s default when unknown.
pub fn default_max_memory_bytes() -> u64 {
    physical_memory_bytes().map_or(udc_core::budget::DEFAULT_MAX_MEMORY_BYTES, |b| b / 2)
}
