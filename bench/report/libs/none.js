// Baseline: the harness and its data, no plot (for the memory and load figures).
window.BENCH = { svaj() {}, family() {} };
