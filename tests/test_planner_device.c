/* SPDX-License-Identifier: MIT */
/* test_planner_device.c - where a planned frame's layers run (ddof_plan_layers_device): on the
 * device whenever the context's device takes the frame, else on the CPU's table; the
 * foreground element composited inside that run, on either, unless it carries part of the
 * frame's alpha (the far field, its gather of the element, the silhouettes and the frame's and
 * the element's own highlights are stages of the run, before the element); else after the
 * passes. The plan says which and why on a device, nothing on the CPU. The whole frames behind
 * each case are tests/gl/test_gl_frame.c's. */
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
static void expect(const char *name, frame_plan plan, layers_device_facts facts, int device,
                   int element, const char *line)
{
    const layers_placement where = ddof_plan_layers_device(&plan, &facts);
    CHECK_MSG(where.device == device && where.element == element,
              "%s: device %d element %d, wanted %d %d", name, where.device, where.element,
              device, element);
    if (line)
        CHECK_MSG(strcmp(plan.text, line) == 0, "%s: the plan says \"%s\", wanted \"%s\"", name,
                  plan.text, line);
    else
        CHECK_MSG(plan.used == 0, "%s: a CPU context's plan says \"%s\"", name, plan.text);
}

int main(void)
{
    const layers_device_facts egl = {.device = "egl"};
    const char *inside = "layers: on egl, the element's composite included\n";

    /* The CPU's layers take the element by the same rule, and say nothing. */
    frame_plan plan = element_plan();
    expect("no device", plan, (layers_device_facts){0}, 0, 1, NULL);
    layers_device_facts carried = {.device = NULL, .carried_alpha = 1};
    expect("no device, a carried alpha", plan, carried, 0, 0, NULL);

    frame_plan none = element_plan();
    none.foreground = 0;
    none.far_field = 1;
    expect("no element", none, egl, 1, 0, "layers: on egl\n");
    expect("an element alone", element_plan(), egl, 1, 1, inside);

    /* The far field (its gather of the element too), the silhouettes and the highlights (the
     * frame's and the element's own) are stages of the layers' run, before the element. */
    plan = element_plan();
    plan.far_field = 1;
    plan.silhouettes = 1;
    plan.highlights = 1;
    expect("every pass", plan, egl, 1, 1, inside);

    /* Only a carried alpha keeps the element out of the run: a fifth channel. */
    layers_device_facts f = egl;
    f.carried_alpha = 1;
    expect("carried alpha", plan, f, 1, 0,
           "layers: on egl; the element after the passes, by the CPU's steps: it carries the "
           "frame's alpha, which the device's frame does not hold\n");
    return test_report("test_planner_device");
}
