; Streams for the toy domain: predicates of their own (the domain declares only done).
(define (stream toy)
  (:stream sample-grasp :inputs (?o) :domain (Graspable ?o) :outputs (?g) :certified (Grasp ?o ?g))
  (:stream test-free :inputs (?o ?g) :domain (Grasp ?o ?g) :certified (Free ?o ?g)))
