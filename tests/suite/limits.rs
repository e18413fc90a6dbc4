//! The memory budget knows the limit the process runs under: a job beyond an address-space cap
//! (`prlimit --as`, what many batch systems set) is refused with the one-line budget message
//! before it starts, instead of aborting on a failed allocation halfway.

use std::process::Command;

/// `prlimit`'s cap for the run: 1.5 GiB of address space.
const CAP_BYTES: u64 = 3 << 29;

/// The budget a refusal names ("the budget is 812 MB"), in bytes.
fn budget_named(stderr: &str) -> Option<u64> {
    let rest = stderr.split("the budget is ").nth(1)?;
    let mut words = rest.split_whitespace();
    let value: f64 = words.next()?.parse().ok()?;
    let unit = words.next()?.trim_end_matches([':', ',']);
    let scale = match unit {
        "GB" => 1e9,
        "MB" => 1e6,
        _ => return None,
    };
    Some((value * scale) as u64)
}

#[test]
fn a_job_beyond_an_address_space_cap_is_refused_before_it_starts() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("scene.hdr");
    // 3072 × 3072: the sensor simulation estimates 52 B per pixel, about 0.49 GB, which half
    // of this machine's memory admits and the cap's budget does not; loading it fits the cap.
    const SIDE: u32 = 3072;
    let img = image::Rgb32FImage::from_fn(SIDE, SIDE, |x, y| {
        let v = 0.05 + (x as f32 / SIDE as f32) * (y as f32 / SIDE as f32);
        image::Rgb([v, v, v])
    });
    image::DynamicImage::ImageRgb32F(img)
        .save(&path)
        .expect("write the scene");
    let out = Command::new("prlimit")
        .arg(format!("--as={CAP_BYTES}"))
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_udc-studio"))
        .args(["sensor", "--hdr"])
        .arg(&path)
        .output()
        .expect("prlimit (util-linux) runs the binary");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("needs about"), "{stderr}");
    let budget = budget_named(&stderr).unwrap_or_else(|| panic!("no budget in {stderr}"));
    assert!(
        budget < CAP_BYTES,
        "budget {budget} under a {CAP_BYTES}-byte cap"
    );
}
