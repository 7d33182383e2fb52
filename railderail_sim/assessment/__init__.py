"""Running behaviour assessed as the acceptance standards define it (docs/assessment.md): EN 14363's
safety, track-loading and ride quantities of the simulation method (`en14363`), ride comfort by EN 12299
and Sperling (`comfort`), their filters and weightings (`filters`), the signals of a run (`signals`), the
assessment of a run (`assess`) and the report study (`study`)."""
