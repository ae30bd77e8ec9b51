namespace camopt::dynamics { int backends_placeholder() { return 0; } }
