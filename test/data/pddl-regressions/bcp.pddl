(define (problem bc1) (:domain briefcase)
  (:objects home office - location doc - portable)
  (:init (at doc home) (is-at home))
  (:goal (and (at doc office) (is-at home))))
