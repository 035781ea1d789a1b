//! Paths per second of the path tracer (to be written).
fn main() {
    divan::main();
}
