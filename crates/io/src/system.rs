//! What the machine and the process may use: the default memory budget of `core::budget`, the
//! smallest of the limits a laptop, a container or a batch system sets. Read from `/proc` and
//! `/sys/fs/cgroup` as text (no system calls), so a fake tree tests every case; under an
//! address-space cap, what the process can still map is measured ([`mappable_bytes`]).

use std::path::{Path, PathBuf};

/// Where the limits are read; [`SystemFiles::real`] on a running system, a folder of fakes in
/// tests.
#[derive(Debug, Clone)]
pub struct SystemFiles {
    /// `/proc` (its `meminfo`, `self/limits`, `self/status` and `self/cgroup`).
    pub proc_root: PathBuf,
    /// `/sys/fs/cgroup`.
    pub cgroup_root: PathBuf,
}

impl SystemFiles {
    /// The running system's.
    pub fn real() -> Self {
        SystemFiles {
            proc_root: PathBuf::from("/proc"),
            cgroup_root: PathBuf::from("/sys/fs/cgroup"),
        }
    }
}

/// Each limit on the process's memory, in bytes, where the system sets one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MemoryLimits {
    /// `MemTotal` of `/proc/meminfo`.
    pub physical: Option<u64>,
    /// The process's cgroup: v2 `memory.max`, or v1 `memory.limit_in_bytes` (a Slurm job's
    /// `--mem`, a container's limit).
    pub cgroup: Option<u64>,
    /// `RLIMIT_AS` (`prlimit --as`, `ulimit -v`): the address space, the process's own mappings
    /// included.
    pub address_space: Option<u64>,
    /// `RLIMIT_DATA` (`ulimit -d`).
    pub data: Option<u64>,
    /// The address space the process already maps (`VmSize`), which `RLIMIT_AS` counts too.
    pub mapped_now: u64,
    /// What the process can still map under `RLIMIT_AS`, measured ([`mappable_bytes`]); when
    /// unknown, the cap less `mapped_now`. `VmSize` alone overstates what is used: an allocator
    /// reserves address space ahead (mimalloc a 1 GiB arena where the cap allows one), which
    /// later allocations fill, so the budget would fall as the cap rises.
    pub mappable: Option<u64>,
}

/// A v1 "no limit" is a huge number (the page-rounded `i64::MAX`); anything above this is none.
const UNLIMITED_ABOVE: u64 = 1 << 60;

/// Of the address space left under `RLIMIT_AS`, the share a job's estimate may take: the rest
/// holds the allocator's reserved-but-unused regions, thread stacks and fragmentation.
const ADDRESS_SPACE_SHARE: f64 = 0.6;

impl MemoryLimits {
    /// Reads every limit from `files`; a missing or unreadable file is no limit.
    pub fn read(files: &SystemFiles) -> Self {
        let proc = |name: &str| std::fs::read_to_string(files.proc_root.join(name)).ok();
        let limits = proc("self/limits");
        let rlimit = |label: &str| limits.as_deref().and_then(|t| rlimit_of(t, label));
        MemoryLimits {
            physical: proc("meminfo").and_then(|t| kib_field(&t, "MemTotal:")),
            cgroup: proc("self/cgroup").and_then(|t| cgroup_limit(&t, &files.cgroup_root)),
            address_space: rlimit("Max address space"),
            data: rlimit("Max data size"),
            mapped_now: proc("self/status")
                .and_then(|t| kib_field(&t, "VmSize:"))
                .unwrap_or(0),
            mappable: None,
        }
    }

    /// The default budget: the smallest of half the physical memory, the cgroup's limit, the
    /// data limit and a share of the address space left under `RLIMIT_AS`; `core::budget`'s
    /// default when none is known.
    pub fn budget_bytes(&self) -> u64 {
        let left_in_address_space = self.address_space.map(|a| {
            let left = self
                .mappable
                .unwrap_or_else(|| a.saturating_sub(self.mapped_now));
            (left as f64 * ADDRESS_SPACE_SHARE) as u64
        });
        [
            self.physical.map(|b| b / 2),
            self.cgroup,
            self.data,
            left_in_address_space,
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(udc_core::budget::DEFAULT_MAX_MEMORY_BYTES)
    }
}

/// A `Name:   123 kB` line of `/proc/meminfo` or `/proc/self/status`, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The soft limit of one row of `/proc/self/limits` (`Max address space  unlimited  unlimited
/// bytes`), or `None` when unlimited.
fn rlimit_of(text: &str, label: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(label))?;
    let soft = line[label.len()..].split_whitespace().next()?;
    soft.parse().ok().filter(|&v| v < UNLIMITED_ABOVE)
}

/// The memory limit of the process's cgroup (`/proc/self/cgroup`): v2's `memory.max` of its
/// group or any parent up to the root, else v1's `memory.limit_in_bytes`.
fn cgroup_limit(self_cgroup: &str, root: &Path) -> Option<u64> {
    let read = |p: PathBuf| {
        std::fs::read_to_string(p)
            .ok()
            .and_then(|t| t.trim().parse::<u64>().ok())
            .filter(|&v| v < UNLIMITED_ABOVE)
    };
    let mut best: Option<u64> = None;
    for line in self_cgroup.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let relative = path.trim_start_matches('/');
        if controllers.is_empty() {
            // v2: the limit that binds is the smallest on the way up.
            let mut dir = root.join(relative);
            loop {
                if let Some(v) = read(dir.join("memory.max")) {
                    best = Some(best.map_or(v, |b| b.min(v)));
                }
                if dir == root || !dir.pop() || !dir.starts_with(root) {
                    break;
                }
            }
        } else if controllers.split(',').any(|c| c == "memory")
            && let Some(v) = read(
                root.join("memory")
                    .join(relative)
                    .join("memory.limit_in_bytes"),
            )
        {
            best = Some(best.map_or(v, |b| b.min(v)));
        }
    }
    best
}

/// Physical memory in bytes (`MemTotal` of `/proc/meminfo`), if the system says.
pub fn physical_memory_bytes() -> Option<u64> {
    MemoryLimits::read(&SystemFiles::real()).physical
}

/// The default budget of this process ([`MemoryLimits::budget_bytes`] of the running system,
/// with what it can still map measured under an address-space cap).
pub fn default_max_memory_bytes() -> u64 {
    let mut limits = MemoryLimits::read(&SystemFiles::real());
    if let Some(cap) = limits.address_space {
        limits.mappable = Some(mappable_bytes(cap));
    }
    limits.budget_bytes()
}

/// Granularity of [`mappable_bytes`]: 16 MiB.
const MAPPABLE_GRAIN: u64 = 16 << 20;

/// Most blocks [`mappable_bytes`] holds at once: the address space left splits into a few
/// (an allocator's reserved arena, the gaps between libraries); more is fragmentation no job
/// could use.
const MAPPABLE_BLOCKS: usize = 8;

/// What the process can still map, up to `cap` bytes, to 16 MiB: blocks reserved one after
/// another, each the largest that still fits (bisected), then all let go. Nothing is written,
/// so no page is touched: the address space is asked for and returned, and counts what the
/// allocator holds reserved but unused as free, as it is for the next job. Used under
/// `RLIMIT_AS`, where a refused reservation is an error, not an overcommitted promise.
pub fn mappable_bytes(cap: u64) -> u64 {
    let fits = |bytes: u64| {
        let mut v: Vec<u8> = Vec::new();
        usize::try_from(bytes).is_ok_and(|n| v.try_reserve_exact(n).is_ok())
    };
    let mut held: Vec<Vec<u8>> = Vec::new();
    let mut total = 0u64;
    while held.len() < MAPPABLE_BLOCKS {
        // The largest whole number of grains that fits: `lo` fits, `hi + 1` does not.
        let (mut lo, mut hi) = (0u64, cap.saturating_sub(total) / MAPPABLE_GRAIN);
        while lo < hi {
            let mid = lo + (hi - lo).div_ceil(2);
            if fits(mid * MAPPABLE_GRAIN) {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        let mut block: Vec<u8> = Vec::new();
        let bytes = lo * MAPPABLE_GRAIN;
        if lo == 0 || !usize::try_from(bytes).is_ok_and(|n| block.try_reserve_exact(n).is_ok()) {
            break;
        }
        held.push(block);
        total += bytes;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(files: &[(&str, &str)]) -> (tempfile::TempDir, SystemFiles) {
        let dir = tempfile::tempdir().expect("temp dir");
        for (path, text) in files {
            let p = dir.path().join(path);
            std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
            std::fs::write(p, text).expect("write");
        }
        let files = SystemFiles {
            proc_root: dir.path().join("proc"),
            cgroup_root: dir.path().join("cgroup"),
        };
        (dir, files)
    }

    const MEMINFO: &str = "MemTotal:       24000000 kB\nMemFree:  1000 kB\n";
    const LIMITS_NONE: &str = "Limit                     Soft Limit           Hard Limit           Units     \n\
        Max data size             unlimited            unlimited            bytes     \n\
        Max address space         unlimited            unlimited            bytes     \n";

    #[test]
    fn without_limits_the_budget_is_half_the_physical_memory() {
        let (_d, f) = tree(&[
            ("proc/meminfo", MEMINFO),
            ("proc/self/limits", LIMITS_NONE),
            ("proc/self/cgroup", "0::/user.slice\n"),
            ("cgroup/user.slice/memory.max", "max\n"),
        ]);
        let l = MemoryLimits::read(&f);
        assert_eq!(l.physical, Some(24_000_000 * 1024));
        assert_eq!((l.cgroup, l.address_space, l.data), (None, None, None));
        assert_eq!(l.budget_bytes(), 12_000_000 * 1024);
    }

    #[test]
    fn a_cgroup_v2_limit_binds_from_the_group_or_a_parent() {
        let (_d, f) = tree(&[
            ("proc/meminfo", MEMINFO),
            ("proc/self/cgroup", "0::/system.slice/job_42/step_0\n"),
            ("cgroup/system.slice/job_42/step_0/memory.max", "max\n"),
            ("cgroup/system.slice/job_42/memory.max", "2147483648\n"),
            ("cgroup/system.slice/memory.max", "8589934592\n"),
        ]);
        assert_eq!(MemoryLimits::read(&f).budget_bytes(), 2 << 30);
    }

    #[test]
    fn a_cgroup_v1_limit_binds_and_its_unlimited_value_does_not() {
        let (_d, f) = tree(&[
            ("proc/meminfo", MEMINFO),
            (
                "proc/self/cgroup",
                "12:cpu,cpuacct:/slurm\n4:memory:/slurm/uid_0/job_7\n",
            ),
            (
                "cgroup/memory/slurm/uid_0/job_7/memory.limit_in_bytes",
                "1073741824\n",
            ),
        ]);
        assert_eq!(MemoryLimits::read(&f).cgroup, Some(1 << 30));
        let (_d, f) = tree(&[
            ("proc/meminfo", MEMINFO),
            ("proc/self/cgroup", "4:memory:/\n"),
            (
                "cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712\n",
            ),
        ]);
        assert_eq!(MemoryLimits::read(&f).cgroup, None);
    }

    #[test]
    fn rlimits_bind_with_the_address_space_already_mapped_taken_off() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
            Max data size             2147483648           unlimited            bytes     \n\
            Max address space         3221225472           4294967296           bytes     \n";
        let (_d, f) = tree(&[
            ("proc/meminfo", MEMINFO),
            ("proc/self/limits", limits),
            ("proc/self/status", "Name: udc\nVmSize:   1048576 kB\n"),
        ]);
        let l = MemoryLimits::read(&f);
        assert_eq!(l.address_space, Some(3 << 30));
        assert_eq!(l.data, Some(2 << 30));
        assert_eq!(l.mapped_now, 1 << 30);
        // 60 % of the 2 GiB left under the 3-GiB address-space cap, below the 2-GiB data limit.
        assert_eq!(l.budget_bytes(), ((2u64 << 30) as f64 * 0.6) as u64);
        // Measured, what can still be mapped replaces the cap less `VmSize` (which counts an
        // allocator's reserved but unused arena as used).
        let measured = MemoryLimits {
            mappable: Some(1 << 30),
            ..l
        };
        assert_eq!(measured.budget_bytes(), ((1u64 << 30) as f64 * 0.6) as u64);
    }

    #[test]
    fn what_can_be_mapped_is_measured_to_the_grain_and_stops_at_the_cap() {
        // Without a cap in this test process every probe fits: the count stops at the cap
        // asked for, a whole number of 16-MiB grains.
        let m = mappable_bytes(100 << 20);
        assert_eq!(m, 96 << 20);
        assert_eq!(mappable_bytes(1 << 20), 0);
    }

    #[test]
    fn nothing_readable_gives_the_core_default() {
        let (_d, f) = tree(&[]);
        assert_eq!(
            MemoryLimits::read(&f).budget_bytes(),
            udc_core::budget::DEFAULT_MAX_MEMORY_BYTES
        );
    }
}
