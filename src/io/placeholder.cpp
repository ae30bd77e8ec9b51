namespace camopt::io { int placeholder() { return 0; } }
