// Outputs of the tools built from d83b7b7 (/work/ref-bin-d83), before the writers moved to
// documents/: the writers must reproduce them byte for byte.
#pragma once

namespace old_output {

// verify: candidate c0002 of a two-vehicle tile, no model accepted (two hypotheses).
const char* const kVerifyNone = R"DOC({
 "format": "canopy.verdict",
 "version": 1,
 "provenance": {
  "tool": "verify",
  "version": "0.1.0",
  "parameters": {
   "accept": "0.544",
   "conf-bias": "-5.365",
   "conf-margin": "5.573",
   "conf-score": "6.317",
   "facing": "0.5",
   "icp-coarse": "0.5",
   "icp-fine": "0.2",
   "icp-iterations": "20",
   "icp-points": "1000",
   "inlier-distance": "0.1",
   "inlier-radius": "0.25",
   "min-height": "0.3",
   "modelbase": "/tmp/docs-tile-cmp/mb",
   "no-flip": "false",
   "occlusion-margin": "0.15",
   "points": "/tmp/dv-cmp/a/cands/c0002/samples.pcd",
   "ray-cell": "0.2",
   "segments": "/tmp/dv-cmp/a/cands/c0002/segments.json",
   "top-k": "3",
   "transform": "3.4169121412122657e-12,0.99999999570584297,9.2673156699609382e-05,500011.99986479053,-0.99999999999999933,0,3.6870570323700491e-08,5400005.9999999516,3.6870570165372478e-08,-9.2673156699609436e-05,0.9999999957058423,200.00088271066755,0,0,0,1"
  },
  "inputs": [
   "/tmp/dv-cmp/a/cands/c0002/match.json",
   "/tmp/dv-cmp/a/cands/c0002/samples.pcd",
   "/tmp/dv-cmp/a/cands/c0002/segments.json",
   "/tmp/docs-tile-cmp/mb"
  ]
 },
 "candidate": "/tmp/dv-cmp/a/cands/c0002/samples.pcd",
 "model": null,
 "confidence": 0.9770387847579326,
 "pose": null,
 "pose_tile": null,
 "fit_rms": null,
 "explained": null,
 "free_space_violation": null,
 "transform": {
  "matrix": [
   3.4169121412122657e-12,
   0.999999995705843,
   9.267315669960938e-05,
   500011.99986479053,
   -0.9999999999999993,
   0.0,
   3.687057032370049e-08,
   5400005.999999952,
   3.687057016537248e-08,
   -9.267315669960944e-05,
   0.9999999957058423,
   200.00088271066755,
   0.0,
   0.0,
   0.0,
   1.0
  ],
  "translation": [
   500011.99986479053,
   5400005.999999952,
   200.00088271066755
  ],
  "heading_deg": -89.99999999980423,
  "pitch_deg": -2.112528058716813e-06,
  "roll_deg": -0.005309780760642498
 },
 "chosen": -1,
 "hypotheses": [
  {
   "model": "tank",
   "gmatch_rank": 1,
   "gmatch_score": 0.2967185260769766,
   "start": "axes",
   "flipped": false,
   "pose": {
    "matrix": [
     0.999917006219571,
     -0.0026662534149771017,
     0.012604434363248243,
     1.6566183810854216,
     -0.004646742858257995,
     0.8378609191765714,
     0.5458639829640715,
     -0.6280951024336151,
     -0.012016174669982897,
     -0.5458772492138851,
     0.8377789925374008,
     0.8366362066849481,
     0.0,
     0.0,
     0.0,
     1.0
    ],
    "translation": [
     1.6566183810854216,
     -0.6280951024336151,
     0.8366362066849481
    ],
    "heading_deg": -0.26625893557458685,
    "pitch_deg": 0.6884926635584018,
    "roll_deg": -33.08732743134161
   },
   "pose_tile": {
    "matrix": [
     -0.004647856411725644,
     0.8378103274108007,
     0.545941620243944,
     500011.37184722454,
     -0.9999170066626135,
     0.0026662332881715947,
     -0.012604403473858975,
     5400004.343381601,
     -0.012015707122544364,
     -0.5459548941843637,
     0.8377284024661485,
     200.83757718239616,
     0.0,
     0.0,
     0.0,
     1.0
    ],
    "translation": [
     500011.37184722454,
     5400004.343381601,
     200.83757718239616
    ],
    "heading_deg": -90.26632274128788,
    "pitch_deg": 0.6884658731293428,
    "roll_deg": -33.092637528293956
   },
   "fit_rms": 0.051571567972486645,
   "explained": 0.3861209964412811,
   "free_space_violation": 0.5997624703087886,
   "score": 0.15454011377756738,
   "flip_score": 0.12857930271066428
  },
  {
   "model": "sedan",
   "gmatch_rank": 2,
   "gmatch_score": 0.08837312439914727,
   "start": "axes-flipped",
   "flipped": true,
   "pose": {
    "matrix": [
     -0.9996574864959089,
     0.008407705926266535,
     0.02478346573301527,
     -0.5659855178786994,
     -0.008267184413906118,
     -0.9999491964549184,
     0.005766989771955222,
     0.009122089185251332,
     0.024830693799179026,
     0.005560125018449796,
     0.9996762084071177,
     1.658249156285726,
     0.0,
     0.0,
     0.0,
     1.0
    ],
    "translation": [
     -0.5659855178786994,
     0.009122089185251332,
     1.658249156285726
    ],
    "heading_deg": -179.52617373099628,
    "pitch_deg": -1.4228401944787823,
    "roll_deg": 0.3186715953594404
   },
   "pose_tile": {
    "matrix": [
     -0.00826488324304386,
     -0.9999486768866137,
     0.005859632897186129,
     500012.0091405549,
     0.9996574874114301,
     -0.00840770572126155,
     -0.024783428874383312,
     5400006.565985531,
     0.024831422980687266,
     0.005652793753145369,
     0.9996756705829841,
     201.65913099359148,
     0.0,
     0.0,
     0.0,
     1.0
    ],
    "translation": [
     500012.0091405549,
     5400006.565985531,
     201.65913099359148
    ],
    "heading_deg": 90.47369438503402,
    "pitch_deg": -1.4228819863877482,
    "roll_deg": 0.32398284973411334
   },
   "fit_rms": 0.04077664149755495,
   "explained": 0.3407473309608541,
   "free_space_violation": 0.38898163606010017,
   "score": 0.20820287668058862,
   "flip_score": 0.19894218460011884
  }
 ]
}
)DOC";

// classify -i c0001.pcd (a tank): a class-level answer with its measurements.
const char* const kClassifyTank = R"DOC({
 "format": "canopy.verdict",
 "version": 1,
 "provenance": {
  "tool": "classify",
  "version": "0.1.0",
  "parameters": {
   "box-ends": "0.8",
   "box-plateau": "0.88",
   "candidate": "",
   "edge-factor": "0.15",
   "ground-cut": "300mm",
   "height-quantile": "0.98",
   "index": "",
   "link-factor": "2.5",
   "max-below-share": "0.25",
   "max-ground-through": "0.4",
   "max-late-returns": "0.4",
   "max-roughness": "0.45",
   "min-density": "4",
   "min-fill": "0.55",
   "min-plateau": "0.45",
   "min-points": "20",
   "model-density": "370",
   "modelbase": "",
   "plateau-drop": "200mm",
   "plateau-split": "0.6",
   "profile-penalty": "1.5",
   "size-gate": "2.5",
   "size-sigma": "150mm",
   "spacing-sigma": "0.5",
   "tail-split": "0.75",
   "transform": ""
  },
  "inputs": [
   "b/cands/c0001.pcd"
  ]
 },
 "candidate": "b/cands/c0001.pcd",
 "level": "class",
 "model": null,
 "class": "tank",
 "group": "tracked",
 "confidence": 0.9086163917139374,
 "reason": null,
 "detail": "",
 "pose": {
  "matrix": [
   1.0,
   0.0,
   0.0,
   0.0,
   0.0,
   1.0,
   0.0,
   -2.980232238769531e-07,
   0.0,
   0.0,
   1.0,
   0.0,
   0.0,
   0.0,
   0.0,
   1.0
  ],
  "translation": [
   0.0,
   -2.980232238769531e-07,
   0.0
  ],
  "heading_deg": 0.0,
  "pitch_deg": -0.0,
  "roll_deg": 0.0
 },
 "pose_tile": null,
 "heading_ambiguity_deg": 180,
 "size": [
  9.452593369249112,
  3.5426522920167507,
  2.288224973678589
 ],
 "measured": {
  "size": [
   9.449995040893555,
   3.540053963661194,
   2.288224973678589
  ],
  "centre": [
   0.0,
   -2.980232238769531e-07
  ],
  "heading_deg": 0.0,
  "spacing": 0.0173221890370471,
  "edge_correction": 0.0025983283555570647
 },
 "density": 3332.6864251803654,
 "density_needed": {
  "class": 4.0,
  "model": 370.0
 },
 "points": 111490,
 "features": {
  "crop_points": 203681,
  "ground_points": 92191,
  "object_points": 111490,
  "crop_spacing": 0.015261958671085854,
  "heading_pca_deg": 0.00879506989715289,
  "heading_hull_deg": 0.0,
  "heading_refined_deg": 0.000296042737353153,
  "ground_density": 3884.65836023819,
  "fill": 0.8579097866861115,
  "plateau_share": 0.8157894736842105,
  "end_low": 0.7703276924347957,
  "end_high": 0.888941399261681,
  "top_roughness": 0.0917980406019423,
  "top_cells": 219,
  "below_share": 0.14995894131766788,
  "ground_through": 0.04638274802722728,
  "interior_points": 79155,
  "below_share_cells": 0.4292237442922374,
  "ground_through_cells": 0.27586206896551724,
  "interior_cells": 261,
  "late_returns": null,
  "multi_returns": null
 },
 "nearest": null,
 "fit_rms": null,
 "explained": null,
 "free_space_violation": null,
 "transform": null,
 "chosen": -1,
 "hypotheses": [],
 "nearest_instance": null,
 "class_score": 1.0,
 "class_margin": 7.559412398294071
}
)DOC";

// classify --transform ... --modelbase: the same with pose_tile, transform and the nearest model.
const char* const kClassifyTankNearest = R"DOC({
 "format": "canopy.verdict",
 "version": 1,
 "provenance": {
  "tool": "classify",
  "version": "0.1.0",
  "parameters": {
   "box-ends": "0.8",
   "box-plateau": "0.88",
   "candidate": "",
   "edge-factor": "0.15",
   "ground-cut": "300mm",
   "height-quantile": "0.98",
   "index": "",
   "link-factor": "2.5",
   "max-below-share": "0.25",
   "max-ground-through": "0.4",
   "max-late-returns": "0.4",
   "max-roughness": "0.45",
   "min-density": "4",
   "min-fill": "0.55",
   "min-plateau": "0.45",
   "min-points": "20",
   "model-density": "370",
   "modelbase": "mb",
   "plateau-drop": "200mm",
   "plateau-split": "0.6",
   "profile-penalty": "1.5",
   "size-gate": "2.5",
   "size-sigma": "150mm",
   "spacing-sigma": "0.5",
   "tail-split": "0.75",
   "transform": "0,-1,0,500000.5,1,0,0,5400000.25,0,0,1,200"
  },
  "inputs": [
   "b/cands/c0001.pcd",
   "mb"
  ]
 },
 "candidate": "b/cands/c0001.pcd",
 "level": "class",
 "model": null,
 "class": "tank",
 "group": "tracked",
 "confidence": 0.9086163917139374,
 "reason": null,
 "detail": "",
 "pose": {
  "matrix": [
   1.0,
   0.0,
   0.0,
   0.0,
   0.0,
   1.0,
   0.0,
   -2.980232238769531e-07,
   0.0,
   0.0,
   1.0,
   0.0,
   0.0,
   0.0,
   0.0,
   1.0
  ],
  "translation": [
   0.0,
   -2.980232238769531e-07,
   0.0
  ],
  "heading_deg": 0.0,
  "pitch_deg": -0.0,
  "roll_deg": 0.0
 },
 "pose_tile": {
  "matrix": [
   0.0,
   -1.0,
   0.0,
   500000.500000298,
   1.0,
   0.0,
   0.0,
   5400000.25,
   0.0,
   0.0,
   1.0,
   200.0,
   0.0,
   0.0,
   0.0,
   1.0
  ],
  "translation": [
   500000.500000298,
   5400000.25,
   200.0
  ],
  "heading_deg": 90.0,
  "pitch_deg": -0.0,
  "roll_deg": 0.0
 },
 "heading_ambiguity_deg": 180,
 "size": [
  9.452593369249112,
  3.5426522920167507,
  2.288224973678589
 ],
 "measured": {
  "size": [
   9.449995040893555,
   3.540053963661194,
   2.288224973678589
  ],
  "centre": [
   0.0,
   -2.980232238769531e-07
  ],
  "heading_deg": 0.0,
  "spacing": 0.0173221890370471,
  "edge_correction": 0.0025983283555570647
 },
 "density": 3332.6864251803654,
 "density_needed": {
  "class": 4.0,
  "model": 370.0
 },
 "points": 111490,
 "features": {
  "crop_points": 203681,
  "ground_points": 92191,
  "object_points": 111490,
  "crop_spacing": 0.015261958671085854,
  "heading_pca_deg": 0.00879506989715289,
  "heading_hull_deg": 0.0,
  "heading_refined_deg": 0.000296042737353153,
  "ground_density": 3884.65836023819,
  "fill": 0.8579097866861115,
  "plateau_share": 0.8157894736842105,
  "end_low": 0.7703276924347957,
  "end_high": 0.888941399261681,
  "top_roughness": 0.0917980406019423,
  "top_cells": 219,
  "below_share": 0.14995894131766788,
  "ground_through": 0.04638274802722728,
  "interior_points": 79155,
  "below_share_cells": 0.4292237442922374,
  "ground_through_cells": 0.27586206896551724,
  "interior_cells": 261,
  "late_returns": null,
  "multi_returns": null
 },
 "nearest": {
  "model": "tank",
  "class": "tank",
  "size": [
   9.447571277618408,
   3.544752597808838,
   2.4512598514556885
  ]
 },
 "fit_rms": null,
 "explained": null,
 "free_space_violation": null,
 "transform": {
  "matrix": [
   0.0,
   -1.0,
   0.0,
   500000.5,
   1.0,
   0.0,
   0.0,
   5400000.25,
   0.0,
   0.0,
   1.0,
   200.0,
   0.0,
   0.0,
   0.0,
   1.0
  ],
  "translation": [
   500000.5,
   5400000.25,
   200.0
  ],
  "heading_deg": 90.0,
  "pitch_deg": -0.0,
  "roll_deg": 0.0
 },
 "chosen": -1,
 "hypotheses": [],
 "nearest_instance": "tank",
 "class_score": 1.0,
 "class_margin": 7.559412398294071
}
)DOC";

// collect: a class-level detection and a rejection classify explained (no model chain ran).
const char* const kCollectClassLevel = R"DOC({
 "format": "canopy.detections",
 "version": 2,
 "provenance": {
  "tool": "collect",
  "version": "0.1.0",
  "parameters": {
   "class-name": "class.json",
   "crs": "EPSG:32633",
   "geojson": "out/col-a2.geojson",
   "model-density": "370",
   "modelbase": "/tmp/dv-cmp/mb",
   "plan": "",
   "plan-key": "TILE",
   "verdict-name": "verdict.json",
   "verdicts": ""
  },
  "inputs": [
   "/tmp/dv-cmp/a2/cands/index.json",
   "/tmp/dv-cmp/a2/cands/c0001/class.json",
   "/tmp/dv-cmp/a2/cands/c0002/class.json"
  ]
 },
 "index": "/tmp/dv-cmp/a2/cands/index.json",
 "tile": "/tmp/docs-tile-cmp/a.pcd",
 "crs": "EPSG:32633",
 "candidates": 2,
 "found": 1,
 "none": 1,
 "failed": 0,
 "by_level": {
  "model": 0,
  "class": 1
 },
 "by_reason": {
  "not_vehicle_shape": 1
 },
 "density": {
  "all": 3979.246376811594,
  "ground": 3878.3248407643314,
  "first": null,
  "cell": 1.0,
  "occupied_cells": 207,
  "open_ground_cells": 157,
  "rule": {
   "density": 3878.3248407643314,
   "voxel": 0.2,
   "voxel_from": "density",
   "min_planarity": 0.2,
   "min_planarity_from": "density",
   "dtm_cell": 0.5,
   "dtm_cell_from": "density"
  }
 },
 "warning": "tile density 3878 points/m²: below the 370 points/m² that model-level recognition needs; class-level answers only; see docs/decisions/classify.md",
 "detections": [
  {
   "candidate": "c0001",
   "level": "class",
   "model": null,
   "class": "sedan",
   "group": "car",
   "confidence": 0.7517103268602106,
   "pose": {
    "x": 500004.9999981089,
    "y": 5400006.000005697,
    "z": 200.0002301813359,
    "heading": 30.00000061267099,
    "pitch": -0.0001364591618373434,
    "roll": 0.0003600773441832573,
    "matrix": [
     0.8660253984354193,
     -0.5000000092636072,
     1.079688171666874e-06,
     500004.9999981089,
     0.5000000092591006,
     0.8660253984132897,
     -6.633397972303825e-06,
     5400006.000005697,
     2.3816616685711855e-06,
     6.284535217775501e-06,
     0.9999999999774163,
     200.0002301813359,
     0.0,
     0.0,
     0.0,
     1.0
    ]
   },
   "heading_ambiguity_deg": 180.0,
   "size": {
    "length": 4.802338054545856,
    "width": 2.0023381022295714,
    "height": 1.4497737884521484
   },
   "density": 4118.331287735849,
   "footprint": [
    [
     500003.42110928014,
     5400003.932383334
    ],
    [
     500007.58005600725,
     5400006.333552406
    ],
    [
     500006.57888693764,
     5400008.06762806
    ],
    [
     500002.41994021053,
     5400005.666458988
    ]
   ],
   "footprint_from": "class",
   "verdict": "/tmp/dv-cmp/a2/cands/c0001/class.json"
  }
 ],
 "rejected": [
  {
   "candidate": "c0002",
   "reason": "not_vehicle_shape",
   "detail": "a flat box: 100% of its length within the top's plateau, both ends at 100% of H or more; 6.06 x 2.44 x 2.59 m is no box-truck or bus (nearest box-truck at 6.8 sigma)",
   "confidence": 0.9999990031052012,
   "density": 4980.570149550558,
   "density_needed": {
    "class": 4.0,
    "model": 370.0
   },
   "model_chain": null,
   "verdict": "/tmp/dv-cmp/a2/cands/c0002/class.json"
  }
 ]
}
)DOC";

const char* const kCollectClassLevelGeojson = R"DOC({
 "type": "FeatureCollection",
 "name": "canopy detections",
 "crs": {
  "type": "name",
  "properties": {
   "name": "urn:ogc:def:crs:EPSG::32633"
  }
 },
 "features": [
  {
   "type": "Feature",
   "id": "c0001",
   "geometry": {
    "type": "Polygon",
    "coordinates": [
     [
      [
       500003.42110928014,
       5400003.932383334
      ],
      [
       500007.58005600725,
       5400006.333552406
      ],
      [
       500006.57888693764,
       5400008.06762806
      ],
      [
       500002.41994021053,
       5400005.666458988
      ],
      [
       500003.42110928014,
       5400003.932383334
      ]
     ]
    ]
   },
   "properties": {
    "candidate": "c0001",
    "level": "class",
    "model": null,
    "class": "sedan",
    "group": "car",
    "confidence": 0.7517103268602106,
    "x": 500004.9999981089,
    "y": 5400006.000005697,
    "z": 200.0002301813359,
    "heading": 30.00000061267099,
    "heading_ambiguity_deg": 180.0,
    "footprint_from": "class"
   }
  }
 ]
}
)DOC";

// collect: a model-level detection (model box footprint) and a failed model chain.
const char* const kCollectModelAndFailed = R"DOC({
 "format": "canopy.detections",
 "version": 2,
 "provenance": {
  "tool": "collect",
  "version": "0.1.0",
  "parameters": {
   "class-name": "class.json",
   "crs": "EPSG:32633",
   "geojson": "out/col-a3.geojson",
   "model-density": "370",
   "modelbase": "/tmp/dv-cmp/mb",
   "plan": "",
   "plan-key": "TILE",
   "verdict-name": "verdict.json",
   "verdicts": ""
  },
  "inputs": [
   "/tmp/dv-cmp/a3/cands/index.json",
   "/tmp/dv-cmp/a3/cands/c0001/verdict.json",
   "/tmp/dv-cmp/a3/cands/c0002/verdict.json",
   "/tmp/dv-cmp/mb/sedan.pcd"
  ]
 },
 "index": "/tmp/dv-cmp/a3/cands/index.json",
 "tile": "/tmp/docs-tile-cmp/a.pcd",
 "crs": "EPSG:32633",
 "candidates": 2,
 "found": 1,
 "none": 0,
 "failed": 1,
 "by_level": {
  "model": 1,
  "class": 0
 },
 "by_reason": {
  "failed": 1
 },
 "density": {
  "all": 3979.246376811594,
  "ground": 3878.3248407643314,
  "first": null,
  "cell": 1.0,
  "occupied_cells": 207,
  "open_ground_cells": 157,
  "rule": {
   "density": 3878.3248407643314,
   "voxel": 0.2,
   "voxel_from": "density",
   "min_planarity": 0.2,
   "min_planarity_from": "density",
   "dtm_cell": 0.5,
   "dtm_cell_from": "density"
  }
 },
 "warning": null,
 "detections": [
  {
   "candidate": "c0001",
   "level": "model",
   "model": "sedan",
   "confidence": 0.9942515089273775,
   "pose": {
    "x": 500004.999097883,
    "y": 5400005.999544823,
    "z": 200.0001916014324,
    "heading": 30.00403232420465,
    "pitch": 0.02639093660732091,
    "roll": 0.021493097720148856,
    "matrix": [
     0.8659901211084124,
     -0.500060762505681,
     0.0005864681349527773,
     500004.999097883,
     0.5000608942741307,
     0.8659902384457148,
     -9.452243282602453e-05,
     5400005.999544823,
     -0.0004606087201956956,
     0.00037512527307823827,
     0.9999998235603028,
     200.0001916014324,
     0.0,
     0.0,
     0.0,
     1.0
    ]
   },
   "footprint": [
    [
     500003.4206717547,
     5400003.932199958
    ],
    [
     500007.5780406021,
     5400006.332848109
    ],
    [
     500006.57692773134,
     5400008.066545369
    ],
    [
     500002.41955888394,
     5400005.665897218
    ]
   ],
   "footprint_from": "model",
   "verdict": "/tmp/dv-cmp/a3/cands/c0001/verdict.json"
  }
 ],
 "rejected": [
  {
   "candidate": "c0002",
   "reason": "failed",
   "detail": "a stage of the model chain failed (see the candidate's .log files)",
   "confidence": null,
   "density": 4980.570122044421,
   "verdict": "/tmp/dv-cmp/a3/cands/c0002/verdict.json"
  }
 ]
}
)DOC";

const char* const kCollectModelAndFailedGeojson = R"DOC({
 "type": "FeatureCollection",
 "name": "canopy detections",
 "crs": {
  "type": "name",
  "properties": {
   "name": "urn:ogc:def:crs:EPSG::32633"
  }
 },
 "features": [
  {
   "type": "Feature",
   "id": "c0001",
   "geometry": {
    "type": "Polygon",
    "coordinates": [
     [
      [
       500003.4206717547,
       5400003.932199958
      ],
      [
       500007.5780406021,
       5400006.332848109
      ],
      [
       500006.57692773134,
       5400008.066545369
      ],
      [
       500002.41955888394,
       5400005.665897218
      ],
      [
       500003.4206717547,
       5400003.932199958
      ]
     ]
    ]
   },
   "properties": {
    "candidate": "c0001",
    "level": "model",
    "model": "sedan",
    "confidence": 0.9942515089273775,
    "x": 500004.999097883,
    "y": 5400005.999544823,
    "z": 200.0001916014324,
    "heading": 30.00403232420465,
    "footprint_from": "model"
   }
  }
 ]
}
)DOC";

}  // namespace old_output
