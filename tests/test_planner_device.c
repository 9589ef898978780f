/* SPDX-License-Identifier: MIT */
/* test_planner_device.c - where a planned frame's layers run (ddof_plan_layers_device): on the
 * context's backend whenever it takes the frame, else on the CPU's table; the foreground
 * element composited inside that run, on either, unless it carries part of the frame's alpha
 * (the far field, its gather of the element, the silhouettes and the frame's and the element's
 * own highlights are stages of the run, before the element); else after the passes. The plan
 * says which and why where the context has a device. The whole frames behind each case are
 * tests/gl/test_gl_frame.c's. */
#include "planner/planner.h"
#include "test_util.h"

#include <stdio.h>
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
                   int element, const char *line)
{
    const layers_placement where = ddof_plan_layers_device(&plan, &facts);
    CHECK_MSG(where.on_backend == on_backend && where.element == element,
              "%s: on the backend %d element %d, wanted %d %d", name, where.on_backend,
              where.element, on_backend, element);
    CHECK_MSG(strcmp(plan.text, line) == 0, "%s: the plan says \"%s\", wanted \"%s\"", name,
              plan.text, line);
}

int main(void)
{
    const layers_device_facts egl = {.backend = "egl", .takes = 1};
    const layers_device_facts cpu = {.backend = "cpu", .takes = 1};
    const char *inside = "layers: on egl\n"; /* the element inside the run goes unsaid */
    const char *after = "; the element after the passes, by the CPU's steps: it carries the "
                        "frame's alpha, which the layers' run does not hold\n";
    char line[256];

    /* The CPU's layers take the element by the same rule; a CPU context had no choice, and
     * its plan says nothing of it. */
    frame_plan plan = element_plan();
    expect("the cpu", plan, cpu, 1, 1, "");
    layers_device_facts carried = cpu;
    carried.carried_alpha = 1;
    expect("the cpu, a carried alpha", plan, carried, 1, 0, "");

    /* A request the device does not take (the double reference, say) runs on the CPU's
     * table, and the plan says why it is not on the context's device. */
    layers_device_facts refused = egl;
    refused.takes = 0;
    expect("not taken", plan, refused, 0, 1,
           "layers: on cpu (the egl device does not take this request)\n");

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
    snprintf(line, sizeof line, "layers: on egl%s", after);
    expect("carried alpha", plan, f, 1, 0, line);
    return test_report("test_planner_device");
}
