/* SPDX-License-Identifier: MIT */
/* test_planner_device.c - where a planned frame's layers run (ddof_plan_layers_device): every
 * stage of them (the highlights, the far field, the silhouettes, the foreground element last,
 * with any alpha it carries) on the context's backend whenever it takes the frame, else on the
 * CPU's table. The plan says which and why where the context has a device. The whole frames
 * behind each case are tests/gl/test_gl_frame.c's. */
#include "planner/planner.h"
#include "test_util.h"

#include <string.h>

/* A plan with only the foreground element switched on. */
static frame_plan element_plan(void)
{
    frame_plan plan;
    memset(&plan, 0, sizeof plan);
    plan.foreground = 1;
    return plan;
}

/* Places plan's layers with facts, and checks the placement and the plan's one new line. */
static void expect(const char *name, frame_plan plan, layers_device_facts facts, int on_backend,
                   const char *line)
{
    const int where = ddof_plan_layers_device(&plan, &facts);
    CHECK_MSG(where == on_backend, "%s: on the backend %d, wanted %d", name, where, on_backend);
    CHECK_MSG(strcmp(plan.text, line) == 0, "%s: the plan says \"%s\", wanted \"%s\"", name,
              plan.text, line);
}

int main(void)
{
    const layers_device_facts egl = {.backend = "egl", .takes = 1};
    const layers_device_facts cpu = {.backend = "cpu", .takes = 1};

    /* A CPU context had no choice, and its plan says nothing of it. */
    frame_plan plan = element_plan();
    expect("the cpu", plan, cpu, 1, "");

    /* A request the device does not take (the double reference, say) runs on the CPU's
     * table, and the plan says why it is not on the context's device. */
    layers_device_facts refused = egl;
    refused.takes = 0;
    expect("not taken", plan, refused, 0,
           "layers: on cpu (the egl device does not take this request)\n");

    frame_plan none = element_plan();
    none.foreground = 0;
    none.far_field = 1;
    expect("no element", none, egl, 1, "layers: on egl\n");
    expect("an element alone", element_plan(), egl, 1, "layers: on egl\n");

    /* The far field (its gather of the element too), the silhouettes and the highlights (the
     * frame's and the element's own) are stages of the layers' run, before the element. */
    plan = element_plan();
    plan.far_field = 1;
    plan.silhouettes = 1;
    plan.highlights = 1;
    expect("every pass", plan, egl, 1, "layers: on egl\n");
    return test_report("test_planner_device");
}
