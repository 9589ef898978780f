# SPDX-License-Identifier: MIT
"""The study's configurations by name: the Defocus nodes, the baselines, the layer settings."""

# The nodes ddof-study knows (study_node_names, study/configs.c). Results of an older study
# may name another 5.x node (defocus-5.0): register_nodes adds it, so old results still report.
STUDY_NODE_IDS = ["defocus", "defocus-4.2", "defocus-5.3"]
NODE_IDS = list(STUDY_NODE_IDS)
NODE_NAMES = {"defocus": "Defocus node 3.4", "defocus-4.2": "Defocus node 4.2",
              "defocus-5.3": "Defocus node 5.3"}
BASELINES_TO_BEAT = NODE_IDS

# The layer settings of the configurations' ids, as the report explains them.
LAYERS_TEXT = {
    "single": "single layer (background off, near spread off)",
    "bg": "+ background layer (on, 1 level)",
    "bg2": "+ background layer (on, 2 levels)",
    "bgnear": "+ background + near spread (both on)",
    "auto": "background, near layer and near spread as the planner decides (AUTO; the near "
            "layer takes the near field where it runs)",
    "auto2": "AUTO, 2 background levels",
    "autospread": "AUTO without the near layer (a blurred near object stays opaque, its "
                  "silhouette spread)",
    "fg": "+ background + the scene's separately rendered foreground element (fg.exr: the near "
          "objects alone) composited over rest.exr (the scene without them), the paper's layers, "
          "where it has one; else near spread on",
    "fgpin": "the same element composited over pinhole.exr (the near objects then lie in the "
             "main image too, as in `ddof pinhole.exr --foreground fg.exr`)",
}

# The baselines' names in the tables and plots, and capitalised at a sentence's start.
BASELINE_NAMES = {"pinhole": "pinhole input", "cod4": "CoD4 preview", "gather": "gather blur",
                  "defocus": "Blender Defocus node 3.4",
                  "defocus-4.2": "Blender Defocus node 4.2",
                  "defocus-5.3": "Blender Defocus node 5.3"}

BASE_NAMES_CAP = {"defocus": "Blender 3.4's Defocus node",
                  "defocus-4.2": "Blender 4.2's Defocus node",
                  "defocus-5.3": "Blender 5.3's Defocus node", "gather": "The gather blur",
                  "cod4": "The CoD4 preview"}

# The baselines' colour and marker in the plots.
BASELINE_STYLE = {"pinhole": ("black", "x"), "cod4": ("tab:orange", "*"),
                  "gather": ("tab:pink", "X"), "defocus": ("tab:green", "^"),
                  "defocus-4.2": ("darkgreen", "<"), "defocus-5.3": ("lime", ">")}


def register_nodes(ids):
    """Adds the Defocus nodes of ids (results' ids) that NODE_IDS lacks ("defocus-5.0" from an
    older study) to NODE_IDS and the name tables, ordered by version."""
    for cid in ids:
        if cid.startswith("defocus-") and cid not in NODE_IDS:
            version = cid[len("defocus-"):]
            NODE_IDS.append(cid)
            NODE_NAMES[cid] = "Defocus node %s" % version
            BASELINE_NAMES[cid] = "Blender Defocus node %s" % version
            BASE_NAMES_CAP[cid] = "Blender %s's Defocus node" % version
            BASELINE_STYLE.setdefault(cid, ("olive", "v"))

    def key(cid):
        if cid == "defocus":
            return (3, 4)
        return tuple(int(x) for x in cid[len("defocus-"):].split(".") if x.isdigit())
    NODE_IDS.sort(key=key)
