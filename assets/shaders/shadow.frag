// Depth-only pass: nothing to write but depth.
void main() {}
