; Streams of blocks-line: positions inside a region, and a collision test.
(define (stream blocks-line)
  (:stream sample-pose
    :inputs (?b ?r)
    :domain (and (Block ?b) (Region ?r))
    :outputs (?p)
    :certified (and (Pose ?b ?p) (Contained ?b ?p ?r)))
  (:stream test-cfree
    :inputs (?b1 ?p1 ?b2 ?p2)
    :domain (and (Pose ?b1 ?p1) (Pose ?b2 ?p2))
    :certified (CFree ?b1 ?p1 ?b2 ?p2)))
