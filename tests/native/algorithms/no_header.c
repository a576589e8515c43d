/* Defines mimics_step without including mimics.h (so no ABI version). */
int mimics_step(const void *robot, void *out) {
    (void)robot;
    (void)out;
    return 0;
}
