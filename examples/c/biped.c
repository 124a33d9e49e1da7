/* Drives the example biped through sinew's C API: load, save to compiled bytes and reload,
 * make a few instances with different look-at targets and foot placements, evaluate them as a
 * batch, print joint positions and the palette size, and show an error message.
 *
 *   cc examples/c/biped.c -I capi/include -L target/release -lsinew_capi -o biped
 *   ./biped graphs/examples/biped/biped.ron
 */
#include <stdio.h>
#include <stdlib.h>

#include "sinew.h"

#define CHECK(call)                                                                      \
    do {                                                                                 \
        SinewStatus s_ = (call);                                                         \
        if (s_ != SINEW_OK) {                                                            \
            fprintf(stderr, "%s failed (%d): %s\n", #call, (int)s_, sinew_last_error_message()); \
            return 1;                                                                    \
        }                                                                                \
    } while (0)

#define INSTANCES 4

int main(int argc, char **argv) {
    const char *path = argc > 1 ? argv[1] : "graphs/examples/biped/biped.ron";
    const char *dynamic[] = {"look_ctrl.translate", "foot_ctrl_*.translateX"};
    SinewRig *authored = NULL;
    CHECK(sinew_rig_load_file(path, dynamic, 2, &authored));

    /* Compiled bytes: what a game ships instead of the RON files. */
    size_t len = 0;
    CHECK(sinew_rig_save_bytes(authored, NULL, 0, &len));
    unsigned char *bytes = malloc(len);
    CHECK(sinew_rig_save_bytes(authored, bytes, len, &len));
    sinew_rig_free(authored);
    SinewRig *rig = NULL;
    CHECK(sinew_rig_load_bytes(bytes, len, &rig));
    free(bytes);
    printf("bytes %zu\n", len);

    size_t joints = sinew_rig_joint_count(rig);
    printf("joints %zu\n", joints);
    int32_t *parents = malloc(joints * sizeof(int32_t));
    CHECK(sinew_rig_joint_parents(rig, parents, joints));

    /* Handles are resolved once; per frame there is no string lookup. */
    uint32_t look, foot, ikfk;
    CHECK(sinew_rig_find_input(rig, "look_ctrl.translate", &look));
    CHECK(sinew_rig_find_input(rig, "foot_ctrl_L.translateX", &foot));
    /* A custom attribute of the rig (attrs: {..} on the arm's settings control). */
    CHECK(sinew_rig_find_input(rig, "arm_settings_L.ikFk", &ikfk));

    SinewInstance *instances[INSTANCES];
    for (int i = 0; i < INSTANCES; i++) {
        CHECK(sinew_instance_new(rig, &instances[i]));
        CHECK(sinew_instance_set_vec3(instances[i], look, 0.1 * i, 0.7, 0.6));
        CHECK(sinew_instance_set_float(instances[i], foot, 0.1 + 0.02 * i));
    }
    /* The last instance has its left arm in IK. */
    CHECK(sinew_instance_set_float(instances[INSTANCES - 1], ikfk, 1.0));
    CHECK(sinew_evaluate_batch(instances, INSTANCES, 10.0));

    float *matrices = malloc(joints * 16 * sizeof(float));
    CHECK(sinew_instance_joint_matrices(instances[INSTANCES - 1], matrices, joints));
    for (size_t j = 0; j < joints; j++) {
        const float *m = matrices + 16 * j; /* column-major: translation in 12..14 */
        printf("joint %s %d %.6f %.6f %.6f\n", sinew_rig_joint_name(rig, j), parents[j], m[12], m[13], m[14]);
    }

    /* Errors come back as codes with a message. */
    uint32_t bad;
    SinewStatus s = sinew_rig_find_input(rig, "look_ctrl.translat", &bad);
    printf("error %d %s\n", (int)s, sinew_last_error_message());
    s = sinew_instance_set_float(instances[0], 99, 1.0);
    printf("error %d %s\n", (int)s, sinew_last_error_message());
    s = sinew_instance_evaluate(NULL, 1.0);
    printf("error %d %s\n", (int)s, sinew_last_error_message());
    s = sinew_instance_set_float(instances[0], ikfk, 2.0); /* ikFk is declared in [0, 1] */
    printf("error %d %s\n", (int)s, sinew_last_error_message());

    for (int i = 0; i < INSTANCES; i++) sinew_instance_free(instances[i]);
    sinew_rig_free(rig);
    free(matrices);
    free(parents);
    printf("ok\n");
    return 0;
}
