/* SPDX-License-Identifier: MIT */
/* test_planner_device.c - where a planned frame's layers run (ddof_plan_layers_device): on the
 * device whenever the context's device takes the frame, else on the CPU's table; the
 * foreground element composited inside that run, on either, unless the run cannot do the
 * element's part: its own highlights, drawn into it, or the part of the frame's alpha it
 * carries (the far field, its gather of the element, the silhouettes and the frame's
 * highlights are stages of the run, before the element); else after the passes. The plan
 * says which and why on a device, nothing on the CPU. The whole frames behind each case are
 * tests/gl/test_gl_frame.c's. */
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
static void expect(const char *name, frame_plan plan, const ddof_params *params,
                   layers_device_facts facts, int device, int element, const char *line)
{
    const layers_placement where = ddof_plan_layers_device(&plan, params, &facts);
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
    ddof_params params;
    ddof_params_init(&params);
    params.highlights = DDOF_LAYER_AUTO;
    params.far_field = DDOF_LAYER_OFF;
    const layers_device_facts egl = {.device = "egl"};
    const char *inside = "layers: on egl, the element's composite included\n";

    /* The CPU's layers take the element by the same rule, and say nothing. */
    frame_plan plan = element_plan();
    expect("no device", plan, &params, (layers_device_facts){0}, 0, 1, NULL);
    plan.far_field = 1;
    expect("no device, the far field", plan, &params, (layers_device_facts){0}, 0, 1, NULL);
    layers_device_facts carried = {.device = NULL, .carried_alpha = 1, .element_bright = 1};
    expect("no device, every reason", plan, &params, carried, 0, 0, NULL);

    frame_plan none = element_plan();
    none.foreground = 0;
    none.far_field = 1;
    expect("no element", none, &params, egl, 1, 0, "layers: on egl\n");
    expect("an element alone", element_plan(), &params, egl, 1, 1, inside);

    const char *after = "layers: on egl; the element after the passes, by the CPU's steps: ";
    char line[256];
    layers_device_facts f = egl;
    f.carried_alpha = 1;
    snprintf(line, sizeof line, "%sit carries the frame's alpha, which the device's frame does "
             "not hold\n", after);
    expect("carried alpha", element_plan(), &params, f, 1, 0, line);

    /* The far field, the silhouettes and the frame's highlights are stages of the layers'
     * run, before the element: no reason. */
    plan = element_plan();
    plan.far_field = 1;
    expect("the far field", plan, &params, egl, 1, 1, inside);
    plan = element_plan();
    plan.silhouettes = 1;
    expect("the silhouettes", plan, &params, egl, 1, 1, inside);
    plan = element_plan();
    plan.highlights = 1;
    expect("the frame's highlights", plan, &params, egl, 1, 1, inside);

    /* The element's own highlights are found in it and drawn into it by the CPU's steps. */
    snprintf(line, sizeof line, "%sits own highlights are drawn into it\n", after);
    f = egl;
    f.element_bright = 1;
    expect("the element's own highlights", element_plan(), &params, f, 1, 0, line);
    /* The far field allowed gathers the element even where the frame's plan has none, in
     * the run too. */
    params.far_field = DDOF_LAYER_AUTO;
    expect("the element's gather", element_plan(), &params, egl, 1, 1, inside);
    params.far_field = DDOF_LAYER_OFF;
    /* With the highlight pass off nothing is drawn into it, so the device takes the element. */
    params.highlights = DDOF_LAYER_OFF;
    expect("highlights off", element_plan(), &params, f, 1, 1, inside);
    return test_report("test_planner_device");
}
