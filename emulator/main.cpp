// gpsemu entry point (placeholder while the core loop is written).
int main() { return 0; }
