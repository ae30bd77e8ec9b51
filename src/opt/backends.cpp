// placeholder replaced below
namespace camopt::opt { int backends_placeholder() { return 0; } }
