; The streams of blocks-2d: poses sampled inside a region, and a collision test.
(define (stream blocks-2d)
  (:stream sample-pose
    :inputs (?b ?r)
    :domain (and (Block ?b) (Region ?r))
    :outputs (?p)
    :certified (and (Pose ?b ?p) (Contained ?b ?p ?r)))
  (:stream test-cfree
    :inputs (?b ?p ?b2 ?p2)
    :domain (and (Pose ?b ?p) (Pose ?b2 ?p2))
    :certified (CFree ?b ?p ?b2 ?p2)))
