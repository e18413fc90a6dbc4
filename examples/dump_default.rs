fn main() {
    print!(
        "{}",
        udc_studio::io::design_file::to_json(&udc_studio::core::Design::default_toled())
    );
}
