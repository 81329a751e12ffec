(define (domain toy) (:predicates (done)) (:action finish :parameters () :precondition () :effect (done)))
